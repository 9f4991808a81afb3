#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "test_support.h"
#include "tools/formats/tetgen.h"
#include "tools/formats/text_records.h"

namespace dtm {
namespace {

std::string bad(const std::string& name) { return std::string(DTM_TEST_SOURCE_DIR) + "/bad/" + name; }

TEST(TetgenReader, ReadsTheCorpusWithMarkers) {
  const NodeFile n = read_tetgen_node(test::data_path("torus_288.node"));
  ASSERT_EQ(n.points.size(), 288u);
  ASSERT_EQ(n.markers.size(), 288u);
  EXPECT_EQ(n.index_base, 0);
  EXPECT_DOUBLE_EQ(n.points[0].x, 3.0);
  EXPECT_DOUBLE_EQ(n.points[1].x, 2.8073058171190732);  // read back to the same double
  EXPECT_EQ(std::count(n.markers.begin(), n.markers.end(), 1), 180);
  const auto tets = read_tetgen_ele(test::data_path("torus_288.ele"), n.points.size());
  EXPECT_EQ(tets.size(), 1080u);
}

TEST(TetgenReader, OneBasedIndicesAndComments) {
  const std::string path = ::testing::TempDir() + "/one_based.node";
  std::ofstream(path) << "# a comment\n4 3\n1 0 0 0 # trailing\n\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  const NodeFile n = read_tetgen_node(path);
  EXPECT_EQ(n.index_base, 1);
  EXPECT_EQ(n.points.size(), 4u);
  EXPECT_TRUE(n.markers.empty());
}

TEST(TetgenReader, KeepsThePointsAttributes) {
  const std::string path = ::testing::TempDir() + "/attributes.node";
  std::ofstream(path)
      << "4 3 2 1\n0 0 0 0 1.5 -2 1\n1 1 0 0 2.5 -3 0\n2 0 1 0 3.5 -4 1\n3 0 0 1 4.5 -5e-3 0\n";
  const NodeFile n = read_tetgen_node(path);
  EXPECT_EQ(n.attribute_count, 2);
  EXPECT_EQ(n.attributes, (std::vector<double>{1.5, -2, 2.5, -3, 3.5, -4, 4.5, -5e-3}));
  EXPECT_EQ(n.markers, (std::vector<int>{1, 0, 1, 0}));
}

struct BadFile {
  const char* file;
  const char* message;  // a part of the expected error
  friend void PrintTo(const BadFile& b, std::ostream* os) { *os << b.file; }
};

class BadNodeFiles : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadNodeFiles, AreRejectedWithFileLineAndProblem) {
  const std::string path = bad(GetParam().file);
  try {
    read_tetgen_node(path);
    FAIL() << path << " was accepted";
  } catch (const FormatError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(GetParam().message), std::string::npos) << what;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Corpus, BadNodeFiles,
    ::testing::Values(BadFile{"empty.node", "empty file"}, BadFile{"missing.node", "cannot open"},
                      BadFile{"truncated.node", "file ends after 2 of 4 points"},
                      BadFile{"wrong_dimension.node", ":1: dimension must be 3"},
                      BadFile{"nan.node", ":4: coordinate is not finite"},
                      BadFile{"inf.node", ":5: coordinate is not finite"},
                      BadFile{"index_gap.node", ":4: point index 3 out of sequence"},
                      BadFile{"extra_data.node", ":5: unexpected data"},
                      BadFile{"missing_field.node", ":3: expected 4 fields, found 3"},
                      BadFile{"garbage_number.node", ":4: expected a coordinate, found '1x'"},
                      BadFile{"bad_header.node", ":1: expected a header"}),
    [](const auto& info) {
      std::string n = info.param.file;
      return n.substr(0, n.find('.'));
    });

TEST(TetgenReader, EleIndicesOutOfRangeAreRejected) {
  const std::string path = ::testing::TempDir() + "/bad.ele";
  std::ofstream(path) << "1 4 0\n0 0 1 2 7\n";
  EXPECT_THROW(read_tetgen_ele(path, 4), FormatError);
  std::ofstream(path) << "1 4 0\n0 0 1 2 3\n";
  EXPECT_EQ(read_tetgen_ele(path, 4).size(), 1u);
}

// A file of several of the reader's pieces (a megabyte of text each, parsed
// on their own threads), with comments and blank lines among the records:
// every record in its place, every line counted.
struct LargeTetgenFiles {
  std::string node, ele;
  size_t points = 0, tets = 0;
  // The line of the .node where point i is.
  std::vector<size_t> line_of;
};
LargeTetgenFiles large_tetgen_files(const std::string& name, size_t points) {
  LargeTetgenFiles f;
  f.points = points;
  f.node = ::testing::TempDir() + "/" + name + ".node";
  f.ele = ::testing::TempDir() + "/" + name + ".ele";
  std::ofstream node(f.node);
  node << "# " << name << "\n" << points << " 3 0 1\n";
  size_t line = 2;
  for (size_t i = 0; i < points; ++i) {
    if (i % 1000 == 7) node << "# a comment\n\n", line += 2;
    node << i << " " << i * 0.5 << ", " << -double(i) << " " << i % 97 << " " << i % 2 << "\n";
    f.line_of.push_back(++line);
  }
  f.tets = points - 3;
  std::ofstream ele(f.ele);
  ele << f.tets << " 4 1\n";
  for (size_t i = 0; i < f.tets; ++i)
    ele << i << " " << i << " " << i + 1 << " " << i + 2 << " " << i + 3 << " " << i % 5 << "\n";
  return f;
}

TEST(TetgenReader, ALargeFileReadsAsOneLoopWould) {
  const LargeTetgenFiles f = large_tetgen_files("large", 150000);
  const NodeFile n = read_tetgen_node(f.node);
  ASSERT_EQ(n.points.size(), f.points);
  ASSERT_EQ(n.markers.size(), f.points);
  for (size_t i = 0; i < f.points; ++i) {
    ASSERT_EQ(n.points[i].x, i * 0.5) << i;
    ASSERT_EQ(n.points[i].y, -double(i)) << i;
    ASSERT_EQ(n.points[i].z, double(i % 97)) << i;
    ASSERT_EQ(n.markers[i], int(i % 2)) << i;
  }
  std::vector<int32_t> regions;
  const auto tets = read_tetgen_ele(f.ele, f.points, 0, {}, &regions);
  ASSERT_EQ(tets.size(), f.tets);
  ASSERT_EQ(regions.size(), f.tets);
  for (size_t i = 0; i < f.tets; ++i) {
    ASSERT_EQ(tets[i],
              (std::array<uint32_t, 4>{uint32_t(i), uint32_t(i + 1), uint32_t(i + 2), uint32_t(i + 3)}));
    ASSERT_EQ(regions[i], int32_t(i % 5));
  }
  // Those a rank keeps: the same tetrahedra, in the same order.
  const auto odd = [](const std::array<uint32_t, 4>& t) { return t[0] % 3 == 1; };
  std::vector<std::array<uint32_t, 4>> want;
  std::copy_if(tets.begin(), tets.end(), std::back_inserter(want), odd);
  EXPECT_EQ(read_tetgen_ele(f.ele, f.points, 0, odd), want);
}

TEST(TetgenReader, AnErrorDeepInALargeFileNamesItsLine) {
  const LargeTetgenFiles f = large_tetgen_files("deep", 150000);
  std::ifstream in(f.node);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  in.close();
  const auto rewrite = [&](size_t point, const std::string& text) {
    std::vector<std::string> changed = lines;
    changed[f.line_of[point] - 1] = text;
    std::ofstream out(f.node);
    for (const auto& l : changed) out << l << "\n";
  };
  const auto error_of = [&]() -> std::string {
    try {
      read_tetgen_node(f.node);
    } catch (const FormatError& e) {
      return e.what();
    }
    return "accepted";
  };
  // Past several pieces; two errors, the earlier one is told.
  rewrite(140000, "140000 1 two 3 0");
  EXPECT_NE(error_of().find(":" + std::to_string(f.line_of[140000]) + ": expected a coordinate, found 'two'"),
            std::string::npos)
      << error_of();
  rewrite(101234, "101235 1 2 3 0");
  EXPECT_NE(error_of().find(":" + std::to_string(f.line_of[101234]) + ": point index 101235 out of sequence"),
            std::string::npos)
      << error_of();
  // A record past those the header counts.
  {
    std::ofstream out(f.node);
    for (const auto& l : lines) out << l << "\n";
    out << "# after\n150000 1 2 3 0\n";
  }
  EXPECT_NE(
      error_of().find(":" + std::to_string(lines.size() + 2) + ": unexpected data after the 150000 points"),
      std::string::npos)
      << error_of();
  // Fewer than it counts.
  {
    std::ofstream out(f.node);
    for (size_t i = 0; i + 1000 < lines.size(); ++i) out << lines[i] << "\n";
  }
  EXPECT_NE(error_of().find("file ends after"), std::string::npos) << error_of();
  // The .ele too: a tetrahedron past those its header counts is an error at
  // its line (comments after them are not), with or without a share kept.
  {
    std::ofstream out(f.ele, std::ios::app);
    out << "# after the tetrahedra\n";
  }
  EXPECT_EQ(read_tetgen_ele(f.ele, f.points, 0).size(), f.tets);
  {
    std::ofstream out(f.ele, std::ios::app);
    out << f.tets << " 0 1 2 3\n";
  }
  for (const bool share : {false, true}) {
    try {
      read_tetgen_ele(f.ele, f.points, 0,
                      share ? std::function<bool(const std::array<uint32_t, 4>&)>(
                                  [](const std::array<uint32_t, 4>& t) { return t[0] % 2 == 0; })
                            : nullptr);
      ADD_FAILURE() << "a tetrahedron past the count accepted";
    } catch (const FormatError& e) {
      EXPECT_NE(
          std::string(e.what()).find("unexpected data after the " + std::to_string(f.tets) + " tetrahedra"),
          std::string::npos)
          << e.what();
    }
  }
}

// Blocks far smaller than the lines: every line end falls between reads.
TEST(TextRecords, SmallBlocksReadEveryRecordWithItsLine) {
  const std::string path = ::testing::TempDir() + "/records.txt";
  std::vector<std::pair<size_t, std::string>> want;  // (line, first field)
  {
    std::ofstream out(path);
    out << "header 1\n";
    size_t line = 1;
    for (int i = 0; i < 3000; ++i) {
      if (i % 7 == 3) out << "  # only a comment\n\n", line += 2;
      const std::string first = std::string(static_cast<size_t>(i % 40), 'x') + std::to_string(i);
      out << first << " , " << i << (i % 11 == 0 ? " # note" : "") << "\n";
      want.emplace_back(++line, first);
    }
    out << "tail";  // no line end
    want.emplace_back(line + 1, "tail");
  }
  for (size_t block : {size_t{1}, size_t{16}, size_t{1000}, size_t{1} << 20}) {
    TextRecords r(path, block);
    TextRecords::Fields fields;
    ASSERT_TRUE(r.next(fields));
    EXPECT_EQ(r.line(), 1u);
    std::vector<std::pair<size_t, std::string>> got;
    size_t first = 0;
    const TextRecords::Found found = r.records(
        want.size(), [&](size_t n, size_t) { first = got.size(), got.resize(got.size() + n); },
        [&](size_t i, size_t line, const TextRecords::Fields& f) {
          got[first + i] = {line, std::string(f[0])};
        },
        [] {});
    EXPECT_EQ(found.records, want.size()) << block;
    EXPECT_EQ(found.extra_line, 0u) << block;
    EXPECT_EQ(got, want) << block;
  }
}

// The same file read in parts (MPI ranks' ranges of its bytes), with blocks
// smaller and larger than a part: the parts' records joined in part order
// are the file's, each with its line in the whole file.
TEST(TextRecords, PartsJoinedReadEveryRecordWithItsLine) {
  const std::string path = ::testing::TempDir() + "/records_parts.txt";
  std::vector<std::pair<size_t, std::string>> want;  // (line, first field)
  {
    std::ofstream out(path);
    out << "# a comment first\nheader 1\n";
    size_t line = 2;
    for (int i = 0; i < 2000; ++i) {
      if (i % 5 == 2) out << "  # only a comment\n\n", line += 2;
      const std::string first = std::string(static_cast<size_t>(i % 70), 'y') + std::to_string(i);
      out << first << " " << i << "\n";
      want.emplace_back(++line, first);
    }
    out << "tail";  // no line end
    want.emplace_back(line + 1, "tail");
  }
  for (size_t block : {size_t{1}, size_t{50}, size_t{3000}, size_t{1} << 20})
    for (int parts : {1, 2, 3, 8, 1000}) {
      std::vector<std::pair<size_t, std::string>> got;
      const auto& [error_line, error_field] = want[want.size() * 2 / 3];
      std::vector<std::string> errors;
      for (int part = 0; part < parts; ++part) {
        TextRecords r(path, block);
        TextRecords::Fields fields;
        ASSERT_TRUE(r.next(fields));
        ASSERT_EQ(r.line(), 2u);
        r.keep_to_part(part, parts);
        size_t first = 0;
        r.records(
            want.size(), [&](size_t n, size_t) { first = got.size(), got.resize(got.size() + n); },
            [&](size_t i, size_t, const TextRecords::Fields& f) {
              got[first + i] = {0, std::string(f[0])};
            },
            [] {});
        // The lines a part numbers are its own, but an error names the
        // line in the whole file.
        TextRecords again(path, block);
        ASSERT_TRUE(again.next(fields));
        again.keep_to_part(part, parts);
        try {
          again.records(
              want.size(), [](size_t, size_t) {},
              [&](size_t, size_t line, const TextRecords::Fields& f) {
                if (f[0] == error_field) again.fail(line, "here");
              },
              [] {});
        } catch (const FormatError& e) {
          errors.push_back(e.what());
        }
      }
      ASSERT_EQ(got.size(), want.size()) << block << " " << parts;
      for (size_t i = 0; i < want.size(); ++i)
        ASSERT_EQ(got[i].second, want[i].second) << block << " " << parts;
      ASSERT_EQ(errors.size(), 1u) << block << " " << parts;
      EXPECT_EQ(errors[0], path + ":" + std::to_string(error_line) + ": here") << block << " " << parts;
    }
}

// The smallest records there can be, the last without its line end: every
// one read. And a header of many attributes over lines of one character
// each: an error, not room for what the header claims.
TEST(TetgenReader, ShortestRecordsAndAClaimOfManyFields) {
  const std::string path = ::testing::TempDir() + "/shortest";
  std::ofstream(path + ".node") << "3 3\n0 0 0 0\n1 1 0 0\n2 0 1 0";
  EXPECT_EQ(read_tetgen_node(path + ".node").points.size(), 3u);
  std::ofstream(path + ".ele") << "2 4\n0 0 1 2 3\n1 0 1 2 3";
  EXPECT_EQ(read_tetgen_ele(path + ".ele", 4).size(), 2u);
  {
    std::ofstream out(path + "_many.node");
    out << "100000 3 1000000 0\n0";
    for (int a = 0; a < 1000003; ++a) out << " 1";
    out << "\n";
    for (int i = 1; i < 100000; ++i) out << "1\n";
  }
  try {
    read_tetgen_node(path + "_many.node");
    FAIL() << "accepted";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find(":3: expected 1000004 fields, found 1"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace dtm
