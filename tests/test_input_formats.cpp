// meshenc's readers on real data: torus_288 and bunny_10k written in every
// input format by writers that are not ours (VTK's, meshio's; see
// convert_corpus.py), read back to the same points, tetrahedra and fields,
// and encoded to byte-identical streams whatever the format.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "format_test_support.h"
#include "test_support.h"
#include "tools/formats/input.h"
#include "tools/formats/mesh_writers.h"
#include "tools/formats/second_order.h"
#include "tools/formats/tetgen.h"
#include "tools/formats/text_cursor.h"

namespace dtm {
namespace {

struct Converted {
  const char* suffix;   // appended to the model's name by convert_corpus.py
  bool tets;            // the format carries the tetrahedra
  bool marker;          // the format carries the made-up point field "marker"
  bool exact;           // coordinates are written so that they read back bit-identical
  bool pieces = false;  // several pieces, a point shared by two in both
};

const Converted kConverted[] = {{"_ascii.vtu", true, true, true},
                                {"_base64.vtu", true, true, true},
                                {"_appended_raw.vtu", true, true, true},
                                {"_appended_base64.vtu", true, true, true},
                                {"_zlib.vtu", true, true, true},
                                {"_lz4_appended_raw.vtu", true, true, true},
                                {"_lzma_appended_base64.vtu", true, true, true},
                                {"_zlib_3_pieces.vtu", true, true, true, true},
                                {"_meshio_zlib.vtu", true, true, true},
                                {"_meshio_lzma.vtu", true, true, true},
                                {"_binary.vtk", true, true, true},
                                {"_ascii.vtk", true, true, false},  // VTK writes 11 digits
                                {"_42.vtk", true, true, true},
                                {".mesh", true, false, true},
                                {"_22.msh", true, true, true},
                                {"_41.msh", true, true, true},
                                {"_22_binary.msh", true, true, true},
                                {"_41_binary.msh", true, true, true},
                                {"_binary.ply", false, false, true},
                                {"_ascii.ply", false, false, true},
                                {".off", false, false, true},
                                {".obj", false, false, true},
                                {".xyz", false, false, true}};

class ConvertedCorpus : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::testing::TempDir() + "/converted";
    std::filesystem::create_directories(dir_);
    for (const char* model : {"torus_288", "bunny_10k"}) {
      const auto r =
          test::run_command(test::kPython + " " + DTM_TEST_SOURCE_DIR + "/convert_corpus.py " +
                            test::data_path(std::string(model) + ".node") + " " + dir_ + " " + model);
      ASSERT_EQ(r.status, 0)
          << "convert_corpus.py failed (scripts/setup.sh --all installs python3-paraview (VTK) and "
             "python3-meshio):\n"
          << r.output;
    }
  }
  static std::string path(const std::string& model, const Converted& c) {
    return dir_ + "/" + model + c.suffix;
  }
  static std::string dir_;
};
std::string ConvertedCorpus::dir_;

// An MPI rank reads only its share of an .ele: the tetrahedra `keep`
// chooses, in the file's order, every line still checked.
TEST(TetgenEle, KeepsWhatItIsToldAndStillChecksTheRest) {
  const NodeFile node = read_tetgen_node(test::data_path("torus_288.node"));
  const std::string ele = test::data_path("torus_288.ele");
  const auto all = read_tetgen_ele(ele, node.points.size(), node.index_base);
  const auto odd = [](const std::array<uint32_t, 4>& t) { return t[0] % 2 == 1; };
  std::vector<std::array<uint32_t, 4>> want;
  std::copy_if(all.begin(), all.end(), std::back_inserter(want), odd);
  ASSERT_FALSE(want.empty());
  EXPECT_EQ(read_tetgen_ele(ele, node.points.size(), node.index_base, odd), want);
  // A vertex out of range in a tetrahedron the filter drops is an error.
  const std::string dir = ::testing::TempDir() + "/tetgen_keep";
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir + "/bad.ele");
    f << "2 4 0\n0 0 1 2 3\n1 1 2 3 99\n";
  }
  EXPECT_THROW(read_tetgen_ele(dir + "/bad.ele", 10, 0, [](const auto& t) { return t[3] < 10; }),
               FormatError);
  // A header that claims more than the file holds is refused, not reserved.
  {
    std::ofstream f(dir + "/claims.ele");
    f << "4000000000 4 0\n0 0 1 2 3\n";
  }
  EXPECT_THROW(read_tetgen_ele(dir + "/claims.ele", 10, 0), FormatError);
  // Kept tetrahedra held in pieces (2^17 each) come back whole and in order.
  {
    std::ofstream f(dir + "/many.ele");
    constexpr uint32_t kCount = 400000;
    f << kCount << " 4 0\n";
    for (uint32_t i = 0; i < kCount; ++i)
      f << i << ' ' << i % 97 << ' ' << i % 89 << ' ' << i % 83 << ' ' << i % 7 << '\n';
  }
  const auto many = read_tetgen_ele(dir + "/many.ele", 100, 0);
  std::vector<std::array<uint32_t, 4>> kept;
  const auto not_last = [](const std::array<uint32_t, 4>& t) { return t[3] != 6; };
  std::copy_if(many.begin(), many.end(), std::back_inserter(kept), not_last);
  ASSERT_GT(kept.size(), size_t{2} << 17);  // two whole pieces and part of a third
  EXPECT_EQ(read_tetgen_ele(dir + "/many.ele", 100, 0, not_last), kept);
}

// MPI ranks read an .ele in parts (each a range of its bytes): joined in
// part order, the parts' records are the file's, whatever the number of
// parts, with comments, blank lines and long lines where the cuts fall; an
// error is found by the one part that holds its line, named by that line
// in the whole file.
TEST(TetgenEle, PartsJoinedAreTheFile) {
  const std::string dir = ::testing::TempDir() + "/tetgen_parts";
  std::filesystem::create_directories(dir);
  constexpr uint32_t kCount = 5000;
  // With a region attribute (TetGen -A) or none.
  const auto ele_lines = [&](bool regions) {
    std::vector<std::string> lines = {"# made by a test", "",
                                      std::to_string(kCount) + " 4 " + (regions ? "1" : "0")};
    for (uint32_t i = 0; i < kCount; ++i) {
      if (i % 97 == 0) lines.push_back("# a comment" + std::string(i % 300, 'x'));
      if (i % 89 == 0) lines.push_back("   ");
      lines.push_back(std::to_string(i) + "  " + std::to_string(i % 61) + " " + std::to_string(i % 59) + " " +
                      std::to_string(i % 53) + " " + std::to_string(i % 51) +
                      (regions ? " " + std::to_string(static_cast<int>(i % 5) - 2) : "") +
                      (i % 7 ? "" : "   # note"));
    }
    return lines;
  };
  const std::vector<std::string> lines = ele_lines(false);
  const auto write = [&](const std::string& name, const std::vector<std::string>& text, bool last_end) {
    std::ofstream f(dir + "/" + name);
    for (size_t i = 0; i < text.size(); ++i) f << text[i] << (i + 1 < text.size() || last_end ? "\n" : "");
  };
  write("all.ele", lines, false);
  write("regions.ele", ele_lines(true), false);
  for (const std::string name : {"all.ele", "regions.ele"}) {
    SCOPED_TRACE(name);
    std::vector<int32_t> regions;
    const auto all = read_tetgen_ele(dir + "/" + name, 64, 0, {}, &regions);
    ASSERT_EQ(all.size(), kCount);
    ASSERT_EQ(regions.size(), name == "all.ele" ? 0u : kCount);
    for (int parts : {1, 2, 3, 5, 16, 97}) {
      std::vector<std::array<uint32_t, 4>> joined;
      std::vector<int32_t> joined_regions;
      uint64_t records = 0;
      for (int part = 0; part < parts; ++part) {
        const ElePart p = read_tetgen_ele_part(
            dir + "/" + name, 64, 0, part, parts, true,
            [&](std::span<const std::array<uint32_t, 4>> block, std::span<const int32_t> block_regions) {
              joined.insert(joined.end(), block.begin(), block.end());
              joined_regions.insert(joined_regions.end(), block_regions.begin(), block_regions.end());
            });
        EXPECT_EQ(p.header_count, kCount);
        records += p.records;
      }
      EXPECT_EQ(records, kCount) << parts;
      EXPECT_EQ(joined, all) << parts;
      EXPECT_EQ(joined_regions, regions) << parts;
    }
  }
  // A vertex out of range on one line: the whole file's message, from the
  // one part that holds that line.
  std::vector<std::string> bad = lines;
  const size_t line = 3 * bad.size() / 5;
  bad[line] = "7 1 2 3 64";
  write("bad.ele", bad, true);
  std::string whole;
  try {
    read_tetgen_ele(dir + "/bad.ele", 64, 0);
  } catch (const FormatError& e) {
    whole = e.what();
  }
  ASSERT_NE(whole.find(":" + std::to_string(line + 1) + ": vertex index 64 out of range"), std::string::npos)
      << whole;
  for (int parts : {2, 3, 7}) {
    int failed = 0;
    for (int part = 0; part < parts; ++part) try {
        read_tetgen_ele_part(dir + "/bad.ele", 64, 0, part, parts, false,
                             [](std::span<const std::array<uint32_t, 4>>, std::span<const int32_t>) {});
      } catch (const FormatError& e) {
        ++failed;
        EXPECT_EQ(std::string(e.what()), whole);
      }
    EXPECT_EQ(failed, 1) << parts;
  }
}

// MPI ranks read a .node in parts too (meshenc's read_node_in_parts()
// joins them): the parts' points, attributes and markers, joined in part
// order, are the file's, each part's first index the base plus the points
// before it; fail_at_node_record() names a record's line in the whole file.
TEST(TetgenNode, PartsJoinedAreTheFile) {
  const std::string dir = ::testing::TempDir() + "/tetgen_node_parts";
  std::filesystem::create_directories(dir);
  constexpr uint32_t kCount = 3000;
  std::vector<std::string> lines = {"# made by a test", std::to_string(kCount) + " 3 2 1"};
  std::vector<size_t> line_of;  // per point, its line (1-based)
  for (uint32_t i = 0; i < kCount; ++i) {
    if (i % 83 == 0) lines.push_back("# a comment" + std::string(i % 400, 'y'));
    if (i % 71 == 0) lines.push_back("");
    lines.push_back(std::to_string(i + 1) + " " + std::to_string(i * 0.25) + " " + std::to_string(i % 37) +
                    " " + std::to_string(-1.5 * (i % 11)) + " " + std::to_string(i % 5) + " " +
                    std::to_string(i * 2) + " " + std::to_string(i % 2));
    line_of.push_back(lines.size());
  }
  {
    std::ofstream f(dir + "/all.node");
    for (const std::string& l : lines) f << l << "\n";
  }
  const std::string path = dir + "/all.node";
  const NodeFile all = read_tetgen_node(path);
  ASSERT_EQ(all.points.size(), kCount);
  ASSERT_EQ(all.index_base, 1);
  for (int parts : {1, 2, 3, 5, 16, 97}) {
    NodeFile joined;
    uint64_t start = 0;
    for (int part = 0; part < parts; ++part) {
      const NodePart p = read_tetgen_node_part(path, part, parts);
      EXPECT_EQ(p.header_count, kCount);
      EXPECT_TRUE(p.has_markers);
      EXPECT_EQ(p.node.attribute_count, 2);
      if (!p.node.points.empty()) {
        EXPECT_EQ(p.first_index, 1 + static_cast<int64_t>(start)) << part;
      }
      start += p.node.points.size();
      joined.points.insert(joined.points.end(), p.node.points.begin(), p.node.points.end());
      joined.attributes.insert(joined.attributes.end(), p.node.attributes.begin(), p.node.attributes.end());
      joined.markers.insert(joined.markers.end(), p.node.markers.begin(), p.node.markers.end());
    }
    ASSERT_EQ(joined.points.size(), all.points.size()) << parts;
    for (size_t i = 0; i < all.points.size(); ++i) {
      ASSERT_EQ(joined.points[i].x, all.points[i].x) << i;
      ASSERT_EQ(joined.points[i].y, all.points[i].y) << i;
      ASSERT_EQ(joined.points[i].z, all.points[i].z) << i;
    }
    EXPECT_EQ(joined.attributes, all.attributes) << parts;
    EXPECT_EQ(joined.markers, all.markers) << parts;
    // A record of a part, named by its line in the whole file.
    if (parts == 5) {
      uint64_t before = 0;
      for (int part = 0; part < 3; ++part)
        before += read_tetgen_node_part(path, part, parts).node.points.size();
      try {
        fail_at_node_record(path, 3, parts, 7, "a problem");
        ADD_FAILURE() << "no error";
      } catch (const FormatError& e) {
        EXPECT_EQ(std::string(e.what()), path + ":" + std::to_string(line_of[before + 7]) + ": a problem");
      }
    }
  }
  // Inside a part, an index out of sequence is that part's error, named
  // by its line in the whole file, as reading the whole file names it.
  std::vector<std::string> bad = lines;
  const size_t at = line_of[2 * kCount / 3] - 1;
  bad[at] = "5" + bad[at].substr(bad[at].find(' '));
  {
    std::ofstream f(dir + "/bad.node");
    for (const std::string& l : bad) f << l << "\n";
  }
  std::string whole;
  try {
    read_tetgen_node(dir + "/bad.node");
  } catch (const FormatError& e) {
    whole = e.what();
  }
  ASSERT_NE(whole.find(":" + std::to_string(at + 1) + ": point index 5 out of sequence"), std::string::npos)
      << whole;
  for (int parts : {2, 3, 7, 1000}) {
    int failed = 0;
    bool first_of_a_part = false;  // then the joining finds it
    uint64_t start = 0;
    for (int part = 0; part < parts; ++part) try {
        const NodePart p = read_tetgen_node_part(dir + "/bad.node", part, parts);
        first_of_a_part |=
            failed == 0 && !p.node.points.empty() && p.first_index != 1 + static_cast<int64_t>(start);
        start += p.node.points.size();
      } catch (const FormatError& e) {
        ++failed;
        EXPECT_EQ(std::string(e.what()), whole);
      }
    EXPECT_EQ(failed + first_of_a_part, 1) << parts;
  }
}

// A mesh read from pieces: its points those of `points`, some more than
// once, each with its marker, and its tetrahedra `tets`, by their corners'
// places.
void expect_same_mesh_in_pieces(const InputMesh& m, const std::vector<InputPoint>& points,
                                const std::vector<std::array<uint32_t, 4>>& tets) {
  const auto key = [](const InputPoint& p) { return std::array<double, 3>{p.x, p.y, p.z}; };
  std::map<std::array<double, 3>, uint32_t> index;
  for (uint32_t i = 0; i < points.size(); ++i) index[key(points[i])] = i;
  ASSERT_GT(m.points.size(), points.size());
  ASSERT_EQ(m.fields.size(), 1u);
  std::vector<uint32_t> original(m.points.size());
  std::set<uint32_t> seen;
  for (size_t i = 0; i < m.points.size(); ++i) {
    const auto it = index.find(key(m.points[i]));
    ASSERT_NE(it, index.end()) << "point " << i << " is not the input's";
    original[i] = it->second;
    seen.insert(it->second);
    EXPECT_EQ(m.fields[0].values[i], static_cast<double>(it->second % 3));
  }
  EXPECT_EQ(seen.size(), points.size());
  ASSERT_EQ(m.tets.size(), tets.size());
  for (size_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) ASSERT_EQ(original[m.tets[t][k]], tets[t][k]) << "tetrahedron " << t;
}

TEST_F(ConvertedCorpus, EveryFormatReadsTheSamePointsTetrahedraAndFields) {
  const NodeFile node = read_tetgen_node(test::data_path("torus_288.node"));
  const auto tets = read_tetgen_ele(test::data_path("torus_288.ele"), node.points.size());
  for (const Converted& c : kConverted) {
    SCOPED_TRACE(c.suffix);
    const InputMesh m = read_input(path("torus_288", c));
    if (c.pieces) {
      expect_same_mesh_in_pieces(m, node.points, tets);
      continue;
    }
    ASSERT_EQ(m.points.size(), node.points.size());
    for (size_t i = 0; i < m.points.size(); ++i) {
      const InputPoint a = m.points[i], b = node.points[i];
      if (c.exact) {
        ASSERT_TRUE(test::same_double(a.x, b.x) && test::same_double(a.y, b.y) && test::same_double(a.z, b.z))
            << "point " << i;
      } else {
        ASSERT_NEAR(a.x, b.x, 1e-9);
        ASSERT_NEAR(a.y, b.y, 1e-9);
        ASSERT_NEAR(a.z, b.z, 1e-9);
      }
    }
    if (c.tets)
      EXPECT_EQ(m.tets, tets);
    else
      EXPECT_TRUE(m.tets.empty());
    if (c.marker) {
      const auto f = std::find_if(m.fields.begin(), m.fields.end(),
                                  [](const VertexField& f) { return f.name == "marker"; });
      ASSERT_NE(f, m.fields.end());
      ASSERT_EQ(f->values.size(), m.points.size());
      for (size_t i = 0; i < m.points.size(); ++i) ASSERT_EQ(f->values[i], static_cast<double>(i % 3));
    }
  }
}

// A UTF-8 byte-order mark first (a Windows editor's) is skipped: the file
// reads as without it. (Every text reader but the VTU's called the first
// line's keyword something else: "expected '$MeshFormat', found
// '$MeshFormat'".)
TEST_F(ConvertedCorpus, AByteOrderMarkFirstIsSkipped) {
  std::vector<std::pair<std::string, std::string>> files;  // with, without
  for (const Converted& c : kConverted)
    if (!c.pieces) files.emplace_back(dir_ + "/bom_torus_288" + c.suffix, path("torus_288", c));
  files.emplace_back(dir_ + "/bom_torus.node", test::data_path("torus_288.node"));
  std::filesystem::copy_file(test::data_path("torus_288.ele"), dir_ + "/bom_torus.ele",
                             std::filesystem::copy_options::overwrite_existing);
  for (const auto& [with, without] : files) {
    SCOPED_TRACE(with);
    std::ofstream(with, std::ios::binary) << kUtf8ByteOrderMark << test::slurp(without);
    InputMesh a, b;
    ASSERT_NO_THROW(a = read_input(with));
    b = read_input(without);
    EXPECT_EQ(a.points.size(), b.points.size());
    EXPECT_TRUE(std::equal(
        a.points.begin(), a.points.end(), b.points.begin(), b.points.end(),
        [](const InputPoint& p, const InputPoint& q) { return p.x == q.x && p.y == q.y && p.z == q.z; }));
    EXPECT_EQ(a.tets, b.tets);
    EXPECT_EQ(a.fields.size(), b.fields.size());
  }
}

// What the point-set formats' files hold beside their numbers, and CGAL's
// readers pass over, is read as before the lines were read again: comments
// after a vertex's numbers, blank lines among a PLY's vertices.
TEST(InputFormats, PointSetsCommentsAndBlankLinesAreRead) {
  const std::string points = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n";
  for (const auto& [name, text] :
       {std::pair<std::string, std::string>{"commented.off",
                                            "OFF\n5 0 0\n0 0 0 # a\n1 0 0\n0 1 0\n0 0 1\n1 1 1 # e\n"},
        {"commented.xyz", "0 0 0 # a\n1 0 0\n0 1 0\n0 0 1\n1 1 1 # e\n"},
        {"commented.obj", "# made by hand\nv 0 0 0 # a\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\n"},
        {"blank_lines.ply",
         "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n\n" +
             points}}) {
    const std::string path = ::testing::TempDir() + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    InputMesh m;
    ASSERT_NO_THROW(m = read_input(path)) << name;
    EXPECT_EQ(m.points.size(), 5u) << name;
  }
}

TEST_F(ConvertedCorpus, TheSamePointSetGivesAByteIdenticalStreamFromEveryFormat) {
  // The point set alone: tetrahedra (which some formats carry) would make
  // the reference solid, and the levels, differ; so would the fields each
  // format keeps of the markers.
  const std::string options = " -q --box 256 --dmax 2 --levels 2 --no-reference --no-fields -o ";
  const std::string reference = dir_ + "/bunny_10k_node.dtm";
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + test::data_path("bunny_10k.node") + options +
                             reference);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string want = test::slurp(reference);
  ASSERT_GT(want.size(), 1000u);
  int compared = 0;
  for (const Converted& c : kConverted) {
    if (!c.exact) continue;
    const std::string out = dir_ + "/bunny_10k" + c.suffix + ".dtm";
    r = test::run_command(std::string(DTM_MESHENC) + " " + path("bunny_10k", c) + options + out);
    ASSERT_EQ(r.status, 0) << c.suffix << ": " << r.output;
    EXPECT_TRUE(test::slurp(out) == want) << c.suffix << ": the stream differs from the .node's";
    ++compared;
  }
  EXPECT_EQ(compared, 22);
}

TEST_F(ConvertedCorpus, InputTetrahedraAreTheReferenceShapeInTheReport) {
  const std::string report = dir_ + "/reference.json";
  auto r = test::run_command(
      std::string(DTM_MESHENC) + " " + dir_ +
      "/torus_288.mesh --scale 25 --dmax 3 --quality-ratio 0 --removal-share 0.3 --report " + report);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("reference shape: the input's 1080 tetrahedra (180 boundary vertices)"),
            std::string::npos)
      << r.output;
  auto j = nlohmann::json::parse(test::slurp(report));
  EXPECT_EQ(j["reference_tetrahedra"], 1080);
  // Level 0 is TetGen's solid exactly; coarser levels stray, within 2 Dmax.
  EXPECT_EQ(j["levels"][0]["reference_to_level_max"], 0.0);
  EXPECT_LT(j["levels"][0]["level_to_reference_max"].get<double>(), 1e-9);  // triangle centroids: rounding
  ASSERT_GE(j["levels"].size(), 3u);
  EXPECT_GT(j["levels"].back()["reference_max_error"].get<double>(), 0.0);
  EXPECT_LE(j["levels"].back()["reference_max_error"].get<double>(), 2 * 3.0);
  EXPECT_GE(j["levels"].back()["reference_max_error"].get<double>(),
            j["levels"].back()["max_boundary_error"].get<double>());
  for (const std::string& args :
       {dir_ + "/torus_288.xyz", test::data_path("torus_288.node") + " --no-reference"}) {
    r = test::run_command(std::string(DTM_MESHENC) + " " + args + " --report " + report);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("reference shape"), std::string::npos) << args;
    j = nlohmann::json::parse(test::slurp(report));
    EXPECT_FALSE(j.contains("reference_tetrahedra")) << args;
  }
}

TEST_F(ConvertedCorpus, FormatOverridesTheExtension) {
  const std::string renamed = dir_ + "/torus_288_ply.data";
  std::filesystem::copy_file(dir_ + "/torus_288_binary.ply", renamed,
                             std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(read_input(renamed, InputFormat::kPly).points.size(), 288u);
  try {
    read_input(renamed);
    ADD_FAILURE() << "an unknown extension was accepted";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find(renamed + ": unknown input format '.data'"), std::string::npos)
        << e.what();
  }
  auto r = test::run_command(std::string(DTM_MESHENC) + " " + renamed + " --format ply -q");
  EXPECT_EQ(r.status, 0) << r.output;
  r = test::run_command(std::string(DTM_MESHENC) + " " + renamed + " --format stl -q");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--format stl: unknown"), std::string::npos) << r.output;
}

TEST(InputFormats, NamesAndExtensions) {
  EXPECT_EQ(input_format_for_path("a/b.NODE"), InputFormat::kTetgen);  // input extensions ignore case
  EXPECT_EQ(input_format_for_path("x.nhdr"), InputFormat::kNrrd);
  EXPECT_EQ(input_format_for_path("x.msh"), InputFormat::kGmsh);
  EXPECT_EQ(input_format_named("medit"), InputFormat::kMedit);
  EXPECT_EQ(input_format_for_path("part.vol"), InputFormat::kNetgen);
  EXPECT_EQ(input_format_for_path("part.VOL.gz"), InputFormat::kNetgen);  // Netgen's gzipped save
  EXPECT_EQ(input_format_named("netgen"), InputFormat::kNetgen);
  EXPECT_THROW(input_format_for_path("x.tar.gz"), FormatError);
  EXPECT_FALSE(input_format_named("stl").has_value());
  EXPECT_THROW(input_format_for_path("x"), FormatError);
  EXPECT_EQ(input_format_for_path("run.exo"), InputFormat::kExodus);
  EXPECT_EQ(input_format_for_path("part.E"), InputFormat::kExodus);
  EXPECT_EQ(input_format_named("exodus"), InputFormat::kExodus);
}

// Small files by hand for what the converted corpus does not show.
std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// What reading `text` as the file `name` fails with ("no error" if it reads).
std::string read_error(const std::string& name, const std::string& text) {
  try {
    read_input(write_temp(name, text));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST(InputFormats, GmshSparseTagsAndNodeData) {
  const std::string path = write_temp(
      "sparse.msh",
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"solid\"\n$EndPhysicalNames\n"
      "$Nodes\n2 4 10 40\n0 1 0 1\n40\n0 0 1\n3 1 0 3\n10\n20\n30\n0 0 0\n1 0 0\n0 1 0\n$EndNodes\n"
      "$Elements\n1 1 7 7\n3 1 4 1\n7 10 20 30 40\n$EndElements\n"
      "$NodeData\n1\n\"t\"\n1\n0.0\n3\n0\n1\n4\n10 1.5\n20 2.5\n30 3.5\n40 4.5\n$EndNodeData\n");
  const InputMesh m = read_input(path);
  ASSERT_EQ(m.points.size(), 4u);
  EXPECT_EQ(m.points[0].z, 1.0);  // node 40 comes first in the file
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.tets[0], (std::array<uint32_t, 4>{1, 2, 3, 0}));
  ASSERT_EQ(m.fields.size(), 1u);
  EXPECT_EQ(m.fields[0].name, "t");
  EXPECT_EQ(m.fields[0].values, (std::vector<double>{4.5, 1.5, 2.5, 3.5}));
  EXPECT_EQ(m.fields[0].type, ScalarType::kFloat64);  // gmsh's node data are doubles
}

// A 4.1 element block of many lines is parsed in pieces on every core:
// every element lands in its place, with its block's region, and a bad line
// deep in the block is told by its line; of two, the earlier.
TEST(InputFormats, GmshElementBlocksReadInPiecesKeepOrderAndTellTheFirstBadLine) {
  constexpr int kTets = 40000;
  const auto file = [&](int bad_late, int bad_early) {
    std::string s = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 8 1 8\n3 1 0 8\n";
    for (int i = 1; i <= 8; ++i) s += std::to_string(i) + "\n";
    for (int i = 0; i < 8; ++i)
      s += std::to_string(i & 1) + " " + std::to_string(i >> 1 & 1) + " " + std::to_string(i >> 2) + "\n";
    s += "$EndNodes\n$Elements\n2 " + std::to_string(kTets + 1) + " 1 " + std::to_string(kTets + 1) + "\n";
    s += "3 7 4 " + std::to_string(kTets) + "\n";
    for (int e = 0; e < kTets; ++e) {
      s += std::to_string(e + 1);
      for (int k = 0; k < 4; ++k) s += " " + std::to_string(e == bad_late && k == 2 ? 99 : (e + k) % 8 + 1);
      if (e == bad_early) s += " x";
      s += "\r\n";  // a file written on Windows
    }
    s += "2 3 2 1\n" + std::to_string(kTets + 1) + " 1 2 3\n$EndElements\n";
    return s;
  };
  // Line 27 is the block's first element.
  const InputMesh m = read_input(write_temp("pieces.msh", file(-1, -1)));
  ASSERT_EQ(m.tets.size(), static_cast<size_t>(kTets));
  for (int e : {0, 16383, 16384, 30001, kTets - 1})
    EXPECT_EQ(m.tets[e], (std::array<uint32_t, 4>{
                             static_cast<uint32_t>(e % 8), static_cast<uint32_t>((e + 1) % 8),
                             static_cast<uint32_t>((e + 2) % 8), static_cast<uint32_t>((e + 3) % 8)}))
        << e;
  ASSERT_EQ(m.tet_regions.size(), static_cast<size_t>(kTets));
  EXPECT_EQ(m.tet_regions[kTets - 1], 7);
  EXPECT_EQ(m.tagged_faces.size(), 1u);
  const auto error_of = [](const std::string& text) { return read_error("bad_pieces.msh", text); };
  EXPECT_NE(error_of(file(30000, -1))
                .find("bad_pieces.msh:" + std::to_string(27 + 30000) + ": node tag 99 out of range"),
            std::string::npos)
      << error_of(file(30000, -1));
  EXPECT_NE(error_of(file(30000, 100))
                .find("bad_pieces.msh:" + std::to_string(27 + 100) + ": expected a node tag, found 'x'"),
            std::string::npos)
      << error_of(file(30000, 100));
  // A file cut inside the block: its counts are more than it can hold.
  std::string cut = file(-1, -1);
  cut.resize(cut.find("\n20000 ") + 1);
  EXPECT_NE(error_of(cut).find(":25: an element count 40001 is more than the file can hold"),
            std::string::npos)
      << error_of(cut);
  // A block that claims a line more than it has: its next block's header
  // (4 fields) read as a tetrahedron.
  std::string short_block = file(-1, -1);
  short_block.replace(short_block.find("3 7 4 40000"), 11, "3 7 4 40001");
  EXPECT_NE(error_of(short_block).find(":" + std::to_string(27 + kTets) + ": a tetrahedron with 3 nodes"),
            std::string::npos)
      << error_of(short_block);
  // 2.x: each line its own type and tags; the same elements, the same line told.
  const auto file2 = [&](int bad) {
    std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n";
    for (int i = 0; i < 8; ++i)
      s += std::to_string(i + 1) + " " + std::to_string(i & 1) + " " + std::to_string(i >> 1 & 1) + " " +
           std::to_string(i >> 2) + "\n";
    s += "$EndNodes\n$Elements\n" + std::to_string(kTets + 1) + "\n1 2 2 5 3 1 2 3\n";
    for (int e = 0; e < kTets; ++e) {
      s += std::to_string(e + 2) + " 4 2 7 1";
      for (int k = 0; k < 4; ++k) s += " " + std::to_string(e == bad && k == 1 ? 99 : (e + k) % 8 + 1);
      s += "\n";
    }
    return s + "$EndElements\n";
  };
  const InputMesh m2 = read_input(write_temp("pieces22.msh", file2(-1)));
  EXPECT_TRUE(m2.tets == m.tets);
  EXPECT_EQ(m2.tet_regions, m.tet_regions);
  EXPECT_EQ(m2.tagged_faces.size(), 1u);
  // Line 18 is the first tetrahedron's (after the count and a triangle).
  EXPECT_NE(error_of(file2(30000))
                .find("bad_pieces.msh:" + std::to_string(18 + 30000) + ": node tag 99 out of range"),
            std::string::npos)
      << error_of(file2(30000));
}

TEST(InputFormats, PointDataKeepTheTypeTheFileStoresThemIn) {
  const std::string path = ::testing::TempDir() + "/typed.vtk";
  std::ofstream(path) << "# vtk DataFile Version 3.0\ntyped\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                         "POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                         "POINT_DATA 4\nSCALARS density short 1\nLOOKUP_TABLE default\n1 2 3 4\n"
                         "FIELD extra 1\nflow 3 4 float\n0 0 0 1 1 1 2 2 2 3 3 3\n";
  const InputMesh m = read_input(path);
  ASSERT_EQ(m.fields.size(), 2u);
  EXPECT_EQ(m.fields[0].type, ScalarType::kInt16);
  EXPECT_EQ(m.fields[1].type, ScalarType::kFloat32);
  EXPECT_EQ(m.fields[1].components, 3);
}

TEST(InputFormats, PlyPropertiesAreKeptAsFields) {
  const std::string path =
      write_temp("props.ply",
                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                 "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
                 "property uchar intensity\nelement face 1\nproperty list uchar int vertex_indices\n"
                 "end_header\n0 0 0 1 0 0 7\n1 0 0 0 1 0 8\n0 1 0 0 0 1 9\n0 0 1 1 0 0 10\n3 0 1 2\n");
  const InputMesh m = read_input(path);
  ASSERT_EQ(m.points.size(), 4u);
  ASSERT_EQ(m.fields.size(), 2u);
  EXPECT_EQ(m.fields[0].name, "normal");
  EXPECT_EQ(m.fields[0].components, 3);
  EXPECT_EQ(m.fields[1].name, "intensity");
  EXPECT_EQ(m.fields[1].values, (std::vector<double>{7, 8, 9, 10}));
  // In the types the file stores; a list property and the faces named.
  EXPECT_EQ(m.fields[0].type, ScalarType::kFloat32);
  EXPECT_EQ(m.fields[1].type, ScalarType::kUInt8);
  EXPECT_EQ(m.left_out,
            (std::vector<std::string>{
                "1 faces (a surface's points are coded, the solid carved by alpha; its faces are not "
                "read)"}));
  const InputMesh typed = read_input(write_temp(
      "typed.ply",
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "property int id\nproperty double t\nproperty list uchar int feat\nend_header\n0 0 0 -5 0.5 2 1 2\n"
      "1 0 0 6 1.5 0\n0 1 0 7 2.5 1 3\n0 0 1 8 3.5 0\n"));
  ASSERT_EQ(typed.fields.size(), 2u);
  EXPECT_EQ(typed.fields[0].type, ScalarType::kInt32);
  EXPECT_EQ(typed.fields[0].values, (std::vector<double>{-5, 6, 7, 8}));
  EXPECT_EQ(typed.fields[1].type, ScalarType::kFloat64);
  EXPECT_EQ(typed.left_out,
            (std::vector<std::string>{"the point property 'feat' (a list, not a number per point)"}));
  const InputMesh off =
      read_input(write_temp("faces.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n"));
  EXPECT_EQ(off.points.size(), 4u);
  EXPECT_EQ(off.left_out,
            (std::vector<std::string>{"2 faces (a surface's points are coded, the solid carved by "
                                      "alpha; its faces are not read)"}));
  const InputMesh obj = read_input(write_temp("faces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n"));
  EXPECT_EQ(obj.left_out.size(), 1u);
}

TEST(InputFormats, MeditSkipsOtherSectionsAndKeepsRefs) {
  const std::string path =
      write_temp("sections.mesh",
                 "MeshVersionFormatted 1\n# comment\nDimension\n3\nVertices\n4\n0 0 0 5\n1 0 0 6\n0 1 0 7\n"
                 "0 0 1 8\nCorners\n1\n1\nTriangles\n1\n1 2 3 0\nTetrahedra\n1\n1 2 3 4 1\nEnd\n");
  const InputMesh m = read_input(path);
  EXPECT_EQ(m.tets.size(), 1u);
  ASSERT_EQ(m.fields.size(), 1u);
  EXPECT_EQ(m.fields[0].values, (std::vector<double>{5, 6, 7, 8}));
}

// Netgen's .vol as Mesh.Save() writes it (the elements before the points,
// comments, then the names; the geometry after endmesh), and gzipped: the
// tetrahedra with their materials, the triangles with their boundary
// conditions, the names; a second-order element and the other sections
// named as left out.
TEST(InputFormats, NetgenVolKeepsMaterialsAndBoundaryConditions) {
  const std::string text =
      "mesh3d\ndimension\n3\ngeomtype\n0\n\n# surfnr    bcnr   domin  domout      np      p1      p2      "
      "p3\n"
      "surfaceelements\n3\n 1 1 1 0 3 1 3 2\n 2 7 1 2 3 2 3 4\n 3 2 1 0 6 1 2 4 5 5 5\n\n"
      "#  matnr      np      p1      p2      p3      p4\nvolumeelements\n3\n1 4 1 2 3 4\n2 4 2 3 4 5\n"
      "2 10 1 2 3 4 5 5 5 5 5 5\n\n"
      "edgesegmentsgi2\n1\n 1 0 1 2 0 0 1 1 1 0 0 0\n\n"
      "points\n5\n 0 0 0\n 1 0 0\n 0 1 0\n 0 0 1\n 1 1 1\n"
      "identificationtypes\n2\n 2 2\n"
      "materials\n2\n1 aluminium\n\n2 steel\n\nbcnames\n2\n1\touter box\n7\tpin\n\nendmesh\n\n"
      "csgsurfaces 1\nplane 6\n0 0 0 0 0 -1\n";
  const InputMesh m = read_input(write_temp("part.vol", text));
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.points[4].x, 1.0);
  // (The second-order elements, whose edge nodes here are all point 5, a
  // corner: read as linear ones, nothing set aside.)
  EXPECT_EQ(m.tets, (std::vector<std::array<uint32_t, 4>>{{0, 1, 2, 3}, {1, 2, 3, 4}, {0, 1, 2, 3}}));
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 2, 2}));
  EXPECT_EQ(m.region_names, (std::map<int32_t, std::string>{{1, "aluminium"}, {2, "steel"}}));
  EXPECT_EQ(m.tagged_faces, (std::vector<std::array<uint32_t, 3>>{{0, 2, 1}, {1, 2, 3}, {0, 1, 3}}));
  EXPECT_EQ(m.face_tags, (std::vector<int32_t>{1, 7, 2}));
  EXPECT_EQ(m.face_tag_names, (std::map<int32_t, std::string>{{1, "outer box"}, {7, "pin"}}));
  EXPECT_TRUE(m.edge_points.empty());
  std::string left_out;
  for (const std::string& l : m.left_out) left_out += l + "\n";
  for (const char* what : {"1 edgesegmentsgi2", "2 identificationtypes", "what follows 'endmesh'"})
    EXPECT_NE(left_out.find(what), std::string::npos) << what << " in:\n" << left_out;
  // Gzipped, as Netgen saves x.vol.gz: the same.
  write_temp("gz_part.vol", text);
  ASSERT_EQ(test::run_command("gzip -c " + ::testing::TempDir() + "/gz_part.vol > " + ::testing::TempDir() +
                              "/gz_part.vol.gz")
                .status,
            0);
  const InputMesh z = read_input(::testing::TempDir() + "/gz_part.vol.gz");
  EXPECT_EQ(z.tets, m.tets);
  EXPECT_EQ(z.face_tags, m.face_tags);
  EXPECT_EQ(z.region_names, m.region_names);
  // A section of another layout than one record a line (here 2 records on
  // one) ends with an error, not with the next section taken for records.
  EXPECT_NE(read_error("odd.vol",
                       "mesh3d\ndimension\n3\nsingular_points\n2\n 1 0.5 2 0.5\npoints\n4\n0 0 0\n1 0 "
                       "0\n0 1 0\n0 0 1\nendmesh\n")
                .find("section 'singular_points' ends before its 2 records"),
            std::string::npos);
  // Cut short, the gzip data says so.
  const std::string gz = test::slurp(::testing::TempDir() + "/gz_part.vol.gz");
  EXPECT_NE(read_error("cut.vol.gz", gz.substr(0, gz.size() / 2)).find("gzip data is damaged or truncated"),
            std::string::npos);
}

// Medit's and Netgen's hexahedra, prisms and pyramids (a cube, a pyramid
// on its top, a prism at its side) and quadrilaterals are read as the
// tetrahedra and triangles that split them, each with its cell's ref or
// material: the same cells from both (Medit's records one a line or split
// over lines; Netgen's second-order hexahedron as its corners), turned as
// each format turns its tetrahedra, filling the cells' volume.
TEST(InputFormats, MeditAndNetgenCellsOfOtherShapesAreSplit) {
  const std::string points =
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n0.5 0.5 1.5\n2 0.5 0\n2 0.5 1\n";
  std::string medit_points;
  for (size_t at = 0, end = 0; (end = points.find('\n', at)) != std::string::npos; at = end + 1)
    medit_points += points.substr(at, end - at) + " 0\n";
  const auto medit = [&](const std::string& hexahedron) {
    return "MeshVersionFormatted 2\nDimension 3\nVertices\n11\n" + medit_points +
           "Quadrilaterals\n1\n1 4 3 2 7\nTetrahedra\n0\nHexahedra\n1\n" + hexahedron +
           "\nPyramids\n1\n5 6 7 8 9 2\nPrisms\n1\n2 3 10 6 7 11 3\nEnd\n";
  };
  const InputMesh m = read_input(write_temp("shapes.mesh", medit("1 2 3 4 5 6 7 8 1")));
  const InputMesh free = read_input(write_temp("shapes_free.mesh", medit("1 2 3 4\n# split\n5 6 7 8 1")));
  // (gmsh's second-order hexahedron, 27 nodes under the linear keyword,
  // its other 19 named corners here: nothing set aside.)
  const InputMesh gmsh_q2 = read_input(
      write_temp("shapes_q2.mesh", medit("1 2 3 4 5 6 7 8 1 2 3 4 5 6 7 8 1 2 3 4 5 6 7 8 1 2 3 1")));
  // (Netgen: the hexahedron second-order, its other 12 nodes named corners
  // here, so that nothing is set aside.)
  const InputMesh n = read_input(
      write_temp("shapes.vol",
                 "mesh3d\ndimension\n3\nsurfaceelements\n1\n 1 7 1 0 4 1 4 3 2\nvolumeelements\n3\n"
                 "1 20 1 2 3 4 5 6 7 8 1 2 3 4 5 6 7 8 1 2 3 4\n2 5 5 6 7 8 9\n3 6 2 3 10 6 7 11\n"
                 "points\n11\n" +
                     points + "endmesh\n"));
  const auto cells = [](const InputMesh& mesh) {
    std::set<std::pair<std::array<uint32_t, 4>, int32_t>> out;
    for (size_t t = 0; t < mesh.tets.size(); ++t) {
      auto sorted = mesh.tets[t];
      std::sort(sorted.begin(), sorted.end());
      out.insert({sorted, mesh.tet_regions.at(t)});
    }
    return out;
  };
  const auto signed_volume = [](const InputMesh& mesh, const std::array<uint32_t, 4>& t) {
    const InputPoint &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]],
                     &d = mesh.points[t[3]];
    const double u[3] = {b.x - a.x, b.y - a.y, b.z - a.z}, v[3] = {c.x - a.x, c.y - a.y, c.z - a.z},
                 w[3] = {d.x - a.x, d.y - a.y, d.z - a.z};
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) /
           6;
  };
  ASSERT_EQ(m.tets.size(), 6u + 2u + 3u);
  EXPECT_EQ(cells(free), cells(m));
  EXPECT_EQ(cells(gmsh_q2), cells(m));
  EXPECT_EQ(cells(n), cells(m));
  EXPECT_EQ(std::count(m.tet_regions.begin(), m.tet_regions.end(), 1), 6);
  EXPECT_EQ(std::count(m.tet_regions.begin(), m.tet_regions.end(), 2), 2);
  EXPECT_EQ(std::count(m.tet_regions.begin(), m.tet_regions.end(), 3), 3);
  // Medit's tetrahedra are positive, Netgen's the other way; either way
  // the cells' volume: the cube's 1, the pyramid's 1/6, the prism's 1/2.
  double medit_volume = 0, netgen_volume = 0;
  for (const auto& t : m.tets) {
    EXPECT_GT(signed_volume(m, t), 0);
    medit_volume += signed_volume(m, t);
  }
  for (const auto& t : n.tets) {
    EXPECT_LT(signed_volume(n, t), 0);
    netgen_volume -= signed_volume(n, t);
  }
  EXPECT_NEAR(medit_volume, 1 + 1.0 / 6 + 0.5, 1e-12);
  EXPECT_NEAR(netgen_volume, 1 + 1.0 / 6 + 0.5, 1e-12);
  // The quadrilateral: two triangles through its least corner, tagged.
  const std::vector<std::array<uint32_t, 3>> bottom{{0, 3, 2}, {0, 2, 1}};
  for (const InputMesh* mesh : {&m, &free, &n}) {
    EXPECT_EQ(mesh->tagged_faces, bottom);
    EXPECT_EQ(mesh->face_tags, (std::vector<int32_t>{7, 7}));
    EXPECT_TRUE(mesh->edge_points.empty());
    std::string left_out;
    for (const std::string& l : mesh->left_out) left_out += l + "\n";
    EXPECT_NE(
        left_out.find("the shapes of its 1 pyramids, 1 prisms, 1 hexahedra: each is read as the tetrahedra"),
        std::string::npos)
        << left_out;
  }
  EXPECT_EQ(m.region_source, "cell refs");
  EXPECT_EQ(m.face_tag_source, "triangle and quadrilateral refs");
}

// A second-order mesh (gmsh -order 2, VTK's quadratic cells, Netgen's
// SecondOrder(), gmsh's Medit TetrahedraP2) is read as its linear cells in every format: the corners
// are the points, in file order, with their fields; the nodes on the edges
// are set aside (each on its edge, here its midpoint) and named as left out.
TEST(InputFormats, SecondOrderElementsAreReadAsTheirLinearCells) {
  // Points in file order: corners c0..c3 with edge nodes between them, and
  // a fifth corner c4, of a linear tetrahedron beside the quadratic one.
  const std::vector<InputPoint> corner = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {2, 2, 2}};
  const auto mid = [&](int a, int b) {
    return InputPoint{(corner[a].x + corner[b].x) / 2, (corner[a].y + corner[b].y) / 2,
                      (corner[a].z + corner[b].z) / 2};
  };
  // File order: c0, m01, c1, m12, c2, m02, m03, c3, m23, m13, c4.
  const std::vector<InputPoint> file = {corner[0], mid(0, 1), corner[1], mid(1, 2), corner[2], mid(0, 2),
                                        mid(0, 3), corner[3], mid(2, 3), mid(1, 3), corner[4]};
  // 0-based file indices of the quadratic tetrahedron's nodes in gmsh's
  // order (corners, then (0,1) (1,2) (0,2) (0,3) (2,3) (1,3)), VTK's
  // (... (1,3) (2,3)) and Netgen's ((0,1) (0,2) (0,3) (1,2) (1,3) (2,3)),
  // and of the 6-node triangle (0, 1, 2) and the linear tetrahedron.
  const std::vector<int> gmsh = {0, 2, 4, 7, 1, 3, 5, 6, 8, 9}, vtk = {0, 2, 4, 7, 1, 3, 5, 6, 9, 8},
                         netgen = {0, 2, 4, 7, 1, 5, 6, 3, 9, 8}, triangle = {0, 2, 4, 1, 3, 5},
                         linear = {2, 4, 7, 10};
  const auto listed = [](const std::vector<int>& nodes, int base) {
    std::string s;
    for (int v : nodes) s += " " + std::to_string(v + base);
    return s;
  };
  std::string points_text;
  for (const InputPoint& p : file)
    points_text += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  std::string numbered_points;  // "tag x y z", 1-based
  for (size_t i = 0; i < file.size(); ++i)
    numbered_points += std::to_string(i + 1) + " " + std::to_string(file[i].x) + " " +
                       std::to_string(file[i].y) + " " + std::to_string(file[i].z) + "\n";
  std::string node_data;  // a field: each node's file index
  for (size_t i = 0; i < file.size(); ++i)
    node_data += std::to_string(i + 1) + " " + std::to_string(i) + "\n";
  const std::string n = std::to_string(file.size());
  const std::map<std::string, std::string> files = {
      {"quadratic22.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + n + "\n" + numbered_points +
                              "$EndNodes\n$Elements\n3\n1 11 2 1 1" + listed(gmsh, 1) + "\n2 9 2 5 1" +
                              listed(triangle, 1) + "\n3 4 2 1 1" + listed(linear, 1) +
                              "\n$EndElements\n$NodeData\n1\n\"index\"\n1\n0.0\n3\n0\n1\n" + n + "\n" +
                              node_data + "$EndNodeData\n"},
      {"quadratic41.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 " + n + " 1 " + n + "\n3 1 0 " +
                              n + "\n" +
                              [&] {
                                std::string t;
                                for (size_t i = 0; i < file.size(); ++i) t += std::to_string(i + 1) + "\n";
                                return t;
                              }() +
                              points_text + "$EndNodes\n$Elements\n3 3 1 3\n3 1 11 1\n1" + listed(gmsh, 1) +
                              "\n2 5 9 1\n2" + listed(triangle, 1) + "\n3 1 4 1\n3" + listed(linear, 1) +
                              "\n$EndElements\n"
                              "$NodeData\n1\n\"index\"\n1\n0.0\n3\n0\n1\n" +
                              n + "\n" + node_data + "$EndNodeData\n"},
      {"quadratic.vtk", "# vtk DataFile Version 3.0\nq\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS " + n +
                            " double\n" + points_text + "CELLS 3 23\n10" + listed(vtk, 0) + "\n6" +
                            listed(triangle, 0) + "\n4" + listed(linear, 0) +
                            "\nCELL_TYPES 3\n24\n22\n10\n"
                            "POINT_DATA " +
                            n + "\nSCALARS index double 1\nLOOKUP_TABLE default\n0 1 2 3 4 5 6 7 8 9 10\n"},
      {"quadratic.vtu",
       "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
       "byte_order=\"LittleEndian\">"
       "<UnstructuredGrid><Piece NumberOfPoints=\"" +
           n +
           "\" NumberOfCells=\"3\"><PointData>"
           "<DataArray type=\"Float64\" Name=\"index\" format=\"ascii\">0 1 2 3 4 5 6 7 8 9 "
           "10</DataArray></PointData>"
           "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">" +
           points_text +
           "</DataArray></Points><Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">" +
           listed(vtk, 0) + listed(triangle, 0) + listed(linear, 0) +
           "</DataArray><DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">10 16 20</DataArray>"
           "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">24 22 10</DataArray></Cells>"
           "</Piece></UnstructuredGrid></VTKFile>\n"},
      // (Medit's refs are the nodes' file indices, its field.)
      {"quadratic.mesh", "MeshVersionFormatted 2\nDimension 3\nVertices\n" + n + "\n" +
                             [&] {
                               std::string t;
                               for (size_t i = 0; i < file.size(); ++i)
                                 t += std::to_string(file[i].x) + " " + std::to_string(file[i].y) + " " +
                                      std::to_string(file[i].z) + " " + std::to_string(i) + "\n";
                               return t;
                             }() +
                             "TrianglesP2\n1\n" + listed(triangle, 1) + " 5\nTetrahedraP2\n1\n" +
                             listed(vtk, 1) + " 1\nTetrahedra\n1\n" + listed(linear, 1) + " 1\nEnd\n"},
      {"quadratic.vol", "mesh3d\ndimension\n3\ngeomtype\n0\nsurfaceelements\n1\n 1 1 1 0 6" +
                            listed(triangle, 1) + "\nvolumeelements\n2\n1 10" + listed(netgen, 1) + "\n1 4" +
                            listed(linear, 1) + "\npoints\n" + n + "\n" + points_text + "endmesh\n"}};
  for (const auto& [name, text] : files) {
    SCOPED_TRACE(name);
    const InputMesh m = read_input(write_temp(name, text));
    ASSERT_EQ(m.points.size(), 5u);
    for (size_t i = 0; i < 5; ++i) {
      EXPECT_EQ(m.points[i].x, corner[i].x);
      EXPECT_EQ(m.points[i].z, corner[i].z);
    }
    ASSERT_EQ(m.tets.size(), 2u);
    EXPECT_EQ(m.tets[0], (std::array<uint32_t, 4>{0, 1, 2, 3}));
    EXPECT_EQ(m.tets[1], (std::array<uint32_t, 4>{1, 2, 3, 4}));
    ASSERT_EQ(m.tagged_faces.size(), 1u);
    EXPECT_EQ(m.tagged_faces[0], (std::array<uint32_t, 3>{0, 1, 2}));
    ASSERT_EQ(m.edge_points.size(), 6u);
    ASSERT_EQ(m.tet_edge_nodes.size(), 2u);
    for (size_t k = 0; k < 6; ++k) {
      const auto [a, b] = std::pair{kTetEdges[k][0], kTetEdges[k][1]};
      const InputPoint p = m.edge_points.at(m.tet_edge_nodes[0][k]), q = mid(a, b);
      EXPECT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << "edge (" << a << "," << b << ")";
      EXPECT_EQ(m.tet_edge_nodes[1][k], InputMesh::kNoEdgeNode);
    }
    if (name.find(".vol") == std::string::npos) {
      ASSERT_EQ(m.fields.size(), 1u);
      EXPECT_EQ(m.fields[0].values, (std::vector<double>{0, 2, 4, 7, 10}));
    }
    const bool named = std::any_of(m.left_out.begin(), m.left_out.end(), [](const std::string& l) {
      return l.find("6 nodes on the edges of second-order elements (1 second-order tetrahedra)") !=
             std::string::npos;
    });
    EXPECT_TRUE(named) << (m.left_out.empty() ? "" : m.left_out[0]);
    EXPECT_EQ(m.left_out.size(), 1u);
  }
  // The linear tetrahedron first: the quadratic one's edge nodes stay its
  // own (the linear one's none).
  const InputMesh m = read_input(write_temp(
      "linear_first.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + n + "\n" + numbered_points +
                              "$EndNodes\n$Elements\n2\n1 4 2 1 1" + listed(linear, 1) + "\n2 11 2 1 1" +
                              listed(gmsh, 1) + "\n$EndElements\n"));
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_EQ(m.tets[1], (std::array<uint32_t, 4>{0, 1, 2, 3}));
  ASSERT_EQ(m.tet_edge_nodes.size(), 2u);
  EXPECT_EQ(m.tet_edge_nodes[0], kNoEdgeNodes);
  for (size_t k = 0; k < 6; ++k) {
    const InputPoint p = m.edge_points.at(m.tet_edge_nodes[1][k]), q = mid(kTetEdges[k][0], kTetEdges[k][1]);
    EXPECT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << k;
  }
  // An 8-node quadrilateral tagging a linear tetrahedron's mesh: its 4
  // other nodes, which no cell holds, are set aside too.
  const InputMesh quad8 = read_input(
      write_temp("quad8.msh",
                 "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n1 0 0 0\n2 2 0 0\n3 0 2 0\n4 0 0 2\n"
                 "5 2 2 0\n6 1 0 0\n7 2 1 0\n8 1 2 0\n9 0 1 0\n$EndNodes\n$Elements\n3\n1 4 2 1 1 1 2 3 4\n"
                 "2 4 2 1 1 2 5 3 4\n3 16 2 7 1 1 2 5 3 6 7 8 9\n$EndElements\n"));
  EXPECT_EQ(quad8.points.size(), 5u);
  EXPECT_EQ(quad8.edge_points.size(), 4u);
  EXPECT_EQ(quad8.tagged_faces.size(), 2u);
  // A surface of 6-node triangles alone: no cell is kept, so no point is
  // set aside (all 11 are the point set).
  const InputMesh surface = read_input(write_temp(
      "surface.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + n + "\n" + numbered_points +
                         "$EndNodes\n$Elements\n1\n1 9 2 5 1" + listed(triangle, 1) + "\n$EndElements\n"));
  EXPECT_EQ(surface.points.size(), file.size());
  EXPECT_TRUE(surface.edge_points.empty());
}

// A gmsh view given at the corners only (a solver's results on a
// second-order mesh's linear cells) is kept, its values at the edge nodes
// left to the stream (their corners' mean); one that misses a corner is
// named as left out; one given at every node keeps its values there.
TEST(InputFormats, GmshNodeDataAtTheCornersOnlyIsKept) {
  // A 10-node tetrahedron (nodes 1-4 its corners, 5-10 its edges' midpoints
  // in gmsh's order) and a linear one beside it (corner 11).
  const std::string nodes =
      "$Nodes\n11\n1 0 0 0\n2 2 0 0\n3 0 2 0\n4 0 0 2\n5 1 0 0\n6 1 1 0\n7 0 1 0\n8 0 0 1\n"
      "9 0 1 1\n10 1 0 1\n11 2 2 2\n$EndNodes\n"
      "$Elements\n2\n1 11 2 1 1 1 2 3 4 5 6 7 8 9 10\n2 4 2 1 1 2 3 4 11\n$EndElements\n";
  const auto view = [](const std::string& name, const std::vector<int>& tags) {
    std::string s = "$NodeData\n1\n\"" + name + "\"\n1\n0.0\n3\n0\n1\n" + std::to_string(tags.size()) + "\n";
    for (int t : tags) s += std::to_string(t) + " " + std::to_string(10 * t) + "\n";
    return s + "$EndNodeData\n";
  };
  const InputMesh m = read_input(write_temp(
      "corner_views.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n" + nodes +
                              view("every node", {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}) +
                              view("corners", {11, 4, 3, 2, 1}) + view("a corner missing", {1, 2, 3, 4}) +
                              view("an edge node missing", {1, 2, 3, 4, 5, 6, 7, 8, 9, 11})));
  ASSERT_EQ(m.points.size(), 5u);
  ASSERT_EQ(m.edge_points.size(), 6u);
  ASSERT_EQ(m.fields.size(), 2u);
  EXPECT_EQ(m.fields[0].name, "every node");
  EXPECT_EQ(m.fields[0].values, (std::vector<double>{10, 20, 30, 40, 110}));
  EXPECT_EQ(m.fields[0].edge_values, (std::vector<double>{50, 60, 70, 80, 90, 100}));
  EXPECT_FALSE(m.fields[0].at_corners_only);
  EXPECT_EQ(m.fields[1].name, "corners");
  EXPECT_EQ(m.fields[1].values, (std::vector<double>{10, 20, 30, 40, 110}));
  EXPECT_TRUE(m.fields[1].edge_values.empty());
  EXPECT_TRUE(m.fields[1].at_corners_only);
  const bool named = std::any_of(m.left_out.begin(), m.left_out.end(), [](const std::string& l) {
    return l.find("$NodeData not given at every node ('a corner missing' at 4 of 11 nodes, ") !=
           std::string::npos;
  });
  EXPECT_TRUE(named);
  // (Given at some edge nodes: not at the corners only, its values there
  // would be lost.)
  EXPECT_TRUE(std::any_of(m.left_out.begin(), m.left_out.end(), [](const std::string& l) {
    return l.find("'an edge node missing' at 10 of 11 nodes") != std::string::npos;
  }));
  for (const std::string& l : m.left_out) EXPECT_EQ(l.find("'corners'"), std::string::npos) << l;
}

// TetGen -o2's .ele (10 nodes a tetrahedron, its own order of the edge
// nodes): made here by Debian's tetgen from torus_288.node, read as the
// linear mesh tetgen makes of it without -o2, each edge node on its edge;
// refused where only a share of it is read (MPI ranks).
TEST(InputFormats, TetgenSecondOrderEleIsReadAsItsLinearMesh) {
  const std::string dir = ::testing::TempDir() + "/tetgen_o2";
  std::filesystem::create_directories(dir + "/linear");
  std::filesystem::create_directories(dir + "/quadratic");
  for (const char* kind : {"linear", "quadratic"}) {
    std::filesystem::copy_file(test::data_path("torus_288.node"), dir + "/" + kind + "/torus.node",
                               std::filesystem::copy_options::overwrite_existing);
    const auto r = test::run_command("cd " + dir + "/" + kind + " && tetgen -Q " +
                                     (std::string(kind) == "quadratic" ? "-o2 " : "") + "torus.node");
    ASSERT_EQ(r.status, 0) << "tetgen (scripts/setup.sh --all installs it):\n" << r.output;
  }
  const InputMesh linear = read_input(dir + "/linear/torus.1.node");
  const InputMesh quadratic = read_input(dir + "/quadratic/torus.1.node");
  ASSERT_EQ(quadratic.points.size(), linear.points.size());
  for (size_t i = 0; i < linear.points.size(); ++i)
    ASSERT_TRUE(quadratic.points[i].x == linear.points[i].x && quadratic.points[i].z == linear.points[i].z)
        << i;
  EXPECT_EQ(quadratic.tets, linear.tets);
  ASSERT_EQ(quadratic.tet_edge_nodes.size(), quadratic.tets.size());
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (size_t t = 0; t < quadratic.tets.size(); ++t)
    for (size_t k = 0; k < 6; ++k) {
      const uint32_t a = quadratic.tets[t][kTetEdges[k][0]], b = quadratic.tets[t][kTetEdges[k][1]];
      edges.insert(std::minmax(a, b));
      const InputPoint p = quadratic.edge_points.at(quadratic.tet_edge_nodes[t][k]);
      const InputPoint& pa = quadratic.points[a];
      const InputPoint& pb = quadratic.points[b];
      ASSERT_NEAR(p.x, (pa.x + pb.x) / 2, 1e-9) << t << " " << k;
      ASSERT_NEAR(p.y, (pa.y + pb.y) / 2, 1e-9) << t << " " << k;
      ASSERT_NEAR(p.z, (pa.z + pb.z) / 2, 1e-9) << t << " " << k;
    }
  EXPECT_EQ(quadratic.edge_points.size(), edges.size());
  // A rank's share of it cannot be read.
  const NodeFile node = read_tetgen_node(dir + "/quadratic/torus.1.node");
  try {
    read_tetgen_ele_part(dir + "/quadratic/torus.1.ele", node.points.size(), node.index_base, 0, 2, false,
                         [](auto, auto) {});
    ADD_FAILURE() << "a share of a second-order .ele was read";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("read whole, on one process"), std::string::npos) << e.what();
  }
}

// What a reader does not keep is named, not dropped in silence.
TEST(InputFormats, WhatIsNotReadIsNamed) {
  const auto has = [](const InputMesh& m, const std::string& part) {
    return std::any_of(m.left_out.begin(), m.left_out.end(),
                       [&](const std::string& s) { return s.find(part) != std::string::npos; });
  };
  const std::string tet = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n";
  // gmsh 2.0, as Netgen writes it: two physical volumes, boundary triangles.
  InputMesh m = read_input(write_temp(
      "netgen.msh",
      "$MeshFormat\n2.0 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n"
      "$EndNodes\n$Elements\n3\n1 4 2 1 1 1 2 3 4\n2 4 2 2 2 2 3 4 5\n3 2 2 7 1 1 2 3\n$EndElements\n"
      "$PhysicalNames\n1\n3 2 \"steel insert\"\n$EndPhysicalNames\n"));
  EXPECT_EQ(m.tets.size(), 2u);
  // Its triangle and the triangle's physical tag: a tagged face.
  EXPECT_EQ(m.tagged_faces.size(), 1u);
  EXPECT_EQ(m.face_tags, (std::vector<int32_t>{7}));
  EXPECT_FALSE(has(m, "elements other than tetrahedra"));
  // Its physical tags are the regions, its volume names theirs: read.
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 2}));
  EXPECT_EQ(m.region_names.at(2), "steel insert");
  EXPECT_FALSE(has(m, "PhysicalNames"));
  // gmsh 2.2 elements without tags: the triangle has nothing to be tagged with.
  m = read_input(write_temp(
      "untagged.msh",
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n"
      "$EndNodes\n$Elements\n2\n1 4 0 1 2 3 4\n2 2 0 1 2 3\n$EndElements\n"));
  EXPECT_TRUE(m.tet_regions.empty());
  EXPECT_TRUE(m.tagged_faces.empty());
  EXPECT_TRUE(has(m, "1 triangles without tags"));
  // gmsh 2.2 writes an element once per physical group it is in: the copies
  // after the first are dropped, a hexahedron's as a tetrahedron's (it was
  // split twice, one set of tetrahedra over the other), and their groups
  // named. A hexahedron listed twice in one group is left as it is.
  std::string cube =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n"
      "5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n9 2 0 0\n$EndNodes\n";
  const std::string hexahedron = " 5 2 1 1 1 2 3 4 5 6 7 8\n";
  m = read_input(write_temp("repeated.msh", cube + "$Elements\n4\n1" + hexahedron +
                                                "2 5 2 2 1 1 2 3 4 5 6 7 8\n" +
                                                "3 4 2 1 2 2 9 3 6\n4 4 2 3 2 9 2 6 3\n$EndElements\n"));
  EXPECT_EQ(m.tets.size(), 7u);  // the cube's 6 and one tetrahedron
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 1, 1, 1, 1, 1, 1}));
  EXPECT_TRUE(has(m, "physical volumes an element is in after its first"));
  EXPECT_TRUE(has(m, "1 hexahedra"));
  m = read_input(write_temp("repeated_one_group.msh", cube + "$Elements\n3\n1" + hexahedron + "2" +
                                                          hexahedron + "3 4 2 2 2 2 9 3 6\n$EndElements\n"));
  EXPECT_EQ(m.tets.size(), 13u);
  EXPECT_FALSE(has(m, "physical volumes an element is in after its first"));
  // gmsh -save_all's 2.x: physical tag 0 on every element, $PhysicalNames
  // listing groups whose members the file does not give. The regions are
  // the elementary entities, without the groups' names (group 2's name is
  // not entity 2's), and the groups are named as left out.
  m = read_input(write_temp("save_all.msh",
                            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n"
                            "3 2 \"steel\"\n2 1 \"base\"\n$EndPhysicalNames\n" +
                                cube.substr(cube.find("$Nodes")) +
                                "$Elements\n3\n1 4 2 0 1 2 9 3 6\n2 4 2 0 2 1 2 3 6\n"
                                "3 2 2 0 1 2 9 3\n$EndElements\n"));
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 2}));
  EXPECT_TRUE(m.region_names.empty());
  EXPECT_EQ(m.face_tags, (std::vector<int32_t>{1}));
  EXPECT_TRUE(m.face_tag_names.empty());
  EXPECT_TRUE(has(m, "the physical groups of $PhysicalNames (volume 2 \"steel\", surface 1 \"base\")"));
  // Medit: tetrahedron refs and triangles.
  m = read_input(
      write_temp("refs.mesh",
                 "MeshVersionFormatted 2\nDimension 3\nVertices\n5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n"
                 "0 0 1 0\n1 1 1 0\nTriangles\n1\n1 2 3 4\nTetrahedra\n2\n1 2 3 4 1\n2 3 4 5 2\nEnd\n"));
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 2}));
  EXPECT_EQ(m.face_tags, (std::vector<int32_t>{4}));
  EXPECT_TRUE(m.left_out.empty());
  // VTK legacy CELL_DATA and a triangle: an integer array may be the
  // regions, a float array is cell data, both on the tetrahedron; the
  // triangle is held as a face the integer array may tag (choose_regions).
  m = read_input(write_temp(
      "cells.vtk", "# vtk DataFile Version 3.0\nc\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n" +
                       tet +
                       "CELLS 2 9\n4 0 1 2 3\n3 1 2 3\nCELL_TYPES 2\n10\n5\n"
                       "CELL_DATA 2\nSCALARS material int 1\nLOOKUP_TABLE default\n1 2\n"
                       "FIELD FieldData 1\nvon%20mises 1 2 float\n0.5 7\n"));
  EXPECT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.tet_arrays["material"], (std::vector<int32_t>{1}));
  ASSERT_EQ(m.cell_fields.size(), 1u);
  EXPECT_EQ(m.cell_fields[0].name, "von mises");
  EXPECT_EQ(m.cell_fields[0].values, (std::vector<double>{0.5}));
  ASSERT_EQ(m.tagged_faces.size(), 1u);
  EXPECT_EQ(m.triangle_arrays["material"], (std::vector<int32_t>{2}));
  EXPECT_FALSE(has(m, "cells other than tetrahedra"));
  // The float array's value on the triangle (7) is not cell data: named.
  EXPECT_TRUE(has(m, "the values of the cell arrays 'von mises' on the triangles"));
  // An integer array that is not the regions becomes cell data: its value
  // on the triangle is named too, unless it is 0, as a float array's 0 or
  // NaN is not (what writers put where an array has no value).
  m = read_input(write_temp(
      "flags.vtk", "# vtk DataFile Version 3.0\nc\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n" +
                       tet +
                       "CELLS 2 9\n4 0 1 2 3\n3 1 2 3\nCELL_TYPES 2\n10\n5\n"
                       "CELL_DATA 2\nSCALARS material int 1\nLOOKUP_TABLE default\n1 2\n"
                       "SCALARS flag int 1\nLOOKUP_TABLE default\n4 5\n"
                       "SCALARS blank int 1\nLOOKUP_TABLE default\n4 0\n"
                       "FIELD FieldData 2\nheat 1 2 float\n0.5 0\nflux 1 2 double\n0.5 nan\n"));
  choose_regions(m, "", "flags.vtk");
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1}));
  EXPECT_EQ(m.face_tags, (std::vector<int32_t>{2}));
  EXPECT_EQ(m.cell_fields.size(), 4u);
  EXPECT_TRUE(has(m, "the values of the integer cell arrays 'flag' on the triangles"));
  EXPECT_FALSE(has(m, "'blank'"));
  EXPECT_FALSE(has(m, "'heat'"));
  EXPECT_FALSE(has(m, "'flux'"));
  // gmsh's $ElementData on a triangle (a face's flux): named, unless 0.
  const std::string with_triangle =
      cube.substr(cube.find("$Nodes")) + "$Elements\n2\n1 4 2 1 1 1 2 3 6\n2 2 2 5 5 1 2 3\n$EndElements\n";
  m = read_input(write_temp(
      "flux.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n" + with_triangle +
                      "$ElementData\n1\n\"flux\"\n1\n0\n3\n0\n1\n2\n1 0.25\n2 7\n$EndElementData\n"
                      "$ElementData\n1\n\"quiet\"\n1\n0\n3\n0\n1\n2\n1 0.5\n2 0\n$EndElementData\n"));
  ASSERT_EQ(m.cell_fields.size(), 2u);
  EXPECT_EQ(m.cell_fields[0].values, (std::vector<double>{0.25}));
  EXPECT_TRUE(has(m, "$ElementData's values on elements other than tetrahedra ('flux' at 1;"));
  EXPECT_FALSE(has(m, "'quiet'"));
  // A TetGen .ele with a region attribute.
  write_temp("regions.node", "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n");
  write_temp("regions.ele", "2 4 1\n0 0 1 2 3 1\n1 1 2 3 4 2\n");
  m = read_input(::testing::TempDir() + "/regions.node");
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 2}));
  EXPECT_TRUE(m.left_out.empty());
  // A second attribute is named.
  write_temp("regions.ele", "2 4 2\n0 0 1 2 3 1 0.5\n1 1 2 3 4 2 0.5\n");
  m = read_input(::testing::TempDir() + "/regions.node");
  EXPECT_TRUE(has(m, "attributes after the first (1 per tetrahedron"));
  // TetGen's attributes are real numbers: a first attribute that is not an
  // integer is kept as cell data, not refused (nor read as regions).
  write_temp("regions.ele", "2 4 1\n0 0 1 2 3 0.5\n1 1 2 3 4 2\n");
  m = read_input(::testing::TempDir() + "/regions.node");
  EXPECT_TRUE(m.tet_regions.empty());
  ASSERT_EQ(m.cell_fields.size(), 1u);
  EXPECT_EQ(m.cell_fields[0].name, "attribute");
  EXPECT_EQ(m.cell_fields[0].values, (std::vector<double>{0.5, 2}));
  EXPECT_TRUE(m.left_out.empty());
  // Nothing to name in a plain tetrahedral mesh.
  EXPECT_TRUE(read_input(test::data_path("torus_288.node")).left_out.empty());
}

// A .vtu in two pieces, the second's cells on its own points.
TEST(InputFormats, VtuPiecesAreOneMeshAndCellDataIsNamed) {
  const std::string piece =
      "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\"><Points><DataArray type=\"Float64\" "
      "NumberOfComponents=\"3\" format=\"ascii\">%s</DataArray></Points>"
      "<CellData><DataArray type=\"Int32\" Name=\"material\" format=\"ascii\">%d</DataArray></CellData>"
      "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray></Cells></Piece>";
  char a[1024], b[1024];
  std::snprintf(a, sizeof a, piece.c_str(), "0 0 0 1 0 0 0 1 0 0 0 1", 1);
  std::snprintf(b, sizeof b, piece.c_str(), "1 0 0 0 1 0 0 0 1 1 1 1", 2);
  InputMesh m =
      read_input(write_temp("two.vtu", std::string("<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>") +
                                           a + b + "</UnstructuredGrid></VTKFile>"));
  ASSERT_EQ(m.points.size(), 8u);
  ASSERT_EQ(m.tets.size(), 2u);
  EXPECT_EQ(m.tets[1], (std::array<uint32_t, 4>{4, 5, 6, 7}));
  // An integer cell array in every piece may be the regions.
  EXPECT_TRUE(m.left_out.empty());
  EXPECT_EQ(m.tet_arrays.at("material"), (std::vector<int32_t>{1, 2}));
  choose_regions(m, "", "two.vtu");
  EXPECT_EQ(m.tet_regions, (std::vector<int32_t>{1, 2}));
  // The cell data in the file's order, integer arrays among the others (as
  // Python's encode() keeps a dict's: the same stream both ways). They
  // came after the others, alphabetically, until 2026-12-07.
  const std::string arrays =
      "<DataArray type=\"Int32\" Name=\"zone\" format=\"ascii\">%d</DataArray>"
      "<DataArray type=\"Float64\" Name=\"stress\" format=\"ascii\">0.5</DataArray>"
      "<DataArray type=\"Int32\" Name=\"count\" format=\"ascii\">7</DataArray>";
  std::string with = piece;
  with.replace(with.find("<DataArray type=\"Int32\" Name=\"material\" format=\"ascii\">%d</DataArray>"),
               std::strlen("<DataArray type=\"Int32\" Name=\"material\" format=\"ascii\">%d</DataArray>"),
               arrays);
  std::snprintf(a, sizeof a, with.c_str(), "0 0 0 1 0 0 0 1 0 0 0 1", 3);
  m = read_input(
      write_temp("ordered.vtu", std::string("<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid>") + a +
                                    "</UnstructuredGrid></VTKFile>"));
  choose_regions(m, "count", "ordered.vtu");
  ASSERT_EQ(m.cell_fields.size(), 2u);
  EXPECT_EQ(m.cell_fields[0].name, "zone");
  EXPECT_EQ(m.cell_fields[1].name, "stress");
}

// A 4.1 binary block of tetrahedra is read on every core (ranges of 2^16
// elements): each in its place, and of two bad node tags the earlier told.
TEST(InputFormats, GmshBinaryBlocksReadInRangesTellTheFirstBadTag) {
  constexpr uint64_t kTets = 70000;
  const auto file = [&](uint64_t bad_early, uint64_t bad_late) {
    std::string s = "$MeshFormat\n4.1 1 8\n";
    const auto put = [&](auto v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); };
    put(int32_t{1});
    s += "\n$EndMeshFormat\n$Nodes\n";
    for (uint64_t v : {uint64_t{1}, uint64_t{8}, uint64_t{1}, uint64_t{8}}) put(v);
    put(int32_t{3}), put(int32_t{1}), put(int32_t{0}), put(uint64_t{8});
    for (uint64_t t = 1; t <= 8; ++t) put(t);
    for (int i = 0; i < 8; ++i) put(double(i & 1)), put(double(i >> 1 & 1)), put(double(i >> 2));
    s += "\n$EndNodes\n$Elements\n";
    for (uint64_t v : {uint64_t{1}, kTets, uint64_t{1}, kTets}) put(v);
    put(int32_t{3}), put(int32_t{5}), put(int32_t{4}), put(kTets);
    for (uint64_t e = 0; e < kTets; ++e) {
      put(e + 1);
      for (uint64_t k = 0; k < 4; ++k) put(e == bad_early ? 98 : e == bad_late ? 99 : (e + k) % 8 + 1);
    }
    return s + "\n$EndElements\n";
  };
  const InputMesh m = read_input(write_temp("binary_ranges.msh", file(kTets, kTets)));
  ASSERT_EQ(m.tets.size(), kTets);
  for (uint64_t e : {uint64_t{0}, uint64_t{65535}, uint64_t{65536}, kTets - 1})
    EXPECT_EQ(m.tets[e], (std::array<uint32_t, 4>{
                             static_cast<uint32_t>(e % 8), static_cast<uint32_t>((e + 1) % 8),
                             static_cast<uint32_t>((e + 2) % 8), static_cast<uint32_t>((e + 3) % 8)}))
        << e;
  EXPECT_EQ(m.tet_regions.at(kTets - 1), 5);
  const auto error_of = [](const std::string& text) { return read_error("binary_ranges_bad.msh", text); };
  EXPECT_NE(error_of(file(kTets, 68000)).find("node tag 99 out of range"), std::string::npos)
      << error_of(file(kTets, 68000));
  EXPECT_NE(error_of(file(100, 68000)).find("node tag 98 out of range"), std::string::npos)
      << error_of(file(100, 68000));
}

// Base64 is decoded fast, on every core, in runs of plain quanta; blanks
// (a line break between quanta, another inside one) are the careful
// loop's, and the runs after them are fast again: the same values.
TEST(InputFormats, VtuBase64ReadsTheSameWithBlanksAnywhere) {
  constexpr size_t kPoints = 30000;  // 720 KB: four ranges of 2^16 quanta
  std::string bytes(8 + 24 * kPoints, '\0');
  const uint64_t count = 24 * kPoints;
  std::memcpy(bytes.data(), &count, 8);
  std::vector<double> xyz(3 * kPoints);
  for (size_t i = 0; i < xyz.size(); ++i) xyz[i] = 0.25 * static_cast<double>(i % 977) - 3.0;
  std::memcpy(bytes.data() + 8, xyz.data(), 24 * kPoints);
  const std::string plain = base64_encode(bytes);
  // Where blanks go; the last case wraps the whole text at 76 characters,
  // as MIME writes base64.
  const std::vector<std::vector<size_t>> cases = {
      {}, {4 * 100000}, {4 * 150000 + 2, 4 * 20}, {4 * 65536, 4 * 65536 - 1}, {}};
  for (size_t k = 0; k < cases.size(); ++k) {
    const std::vector<size_t>& breaks = cases[k];
    std::string text = plain;
    std::vector<size_t> at = breaks;
    std::sort(at.rbegin(), at.rend());  // from the end: the places before stay
    for (size_t p : at) text.insert(p, "\n  ");
    if (k + 1 == cases.size()) {
      text.clear();
      for (size_t p = 0; p < plain.size(); p += 76) text += plain.substr(p, 76) + "\n";
    }
    const InputMesh m = read_input(
        write_temp("base64.vtu",
                   "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\"><UnstructuredGrid><Piece "
                   "NumberOfPoints=\"" +
                       std::to_string(kPoints) +
                       "\" NumberOfCells=\"0\"><Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" "
                       "format=\"binary\">" +
                       text + "</DataArray></Points></Piece></UnstructuredGrid></VTKFile>"));
    ASSERT_EQ(m.points.size(), kPoints) << breaks.size();
    for (size_t i : {size_t{0}, size_t{21845}, kPoints / 2, kPoints - 1})
      EXPECT_EQ(m.points[i].y, xyz[3 * i + 1]) << i << ", " << breaks.size() << " breaks";
    bool all = true;
    for (size_t i = 0; i < kPoints; ++i)
      all = all && m.points[i].x == xyz[3 * i] && m.points[i].y == xyz[3 * i + 1] &&
            m.points[i].z == xyz[3 * i + 2];
    EXPECT_TRUE(all) << breaks.size() << " breaks";
  }
}

// Medit records one a line, as meshers write them, are read in pieces on
// every core; a section written otherwise (records over several lines or
// joined, comments among them) is read token by token: the same mesh, and
// an error at the same line either way.
TEST(InputFormats, MeditReadsTheSameOneRecordALineOrFreeForm) {
  constexpr int kVertices = 20000, kTets = 40000, kTriangles = 3000;
  // `split`: every 1000th record of a section over two lines, a comment and
  // a blank line after it; `bad`: the tetrahedron of that number names
  // vertex kVertices + 1.
  const auto file = [&](bool split, int bad) {
    std::string s = "MeshVersionFormatted 2\nDimension 3\nVertices\n" + std::to_string(kVertices) + "\n";
    const auto record = [&](int i, const std::string& first, const std::string& rest) {
      s += first + (split && i % 1000 == 999 ? "\n# a comment\n\n" : " ") + rest + "\n";
    };
    for (int v = 0; v < kVertices; ++v)
      record(v, std::to_string(v % 97) + " " + std::to_string(v % 89 * 0.5),
             std::to_string(v / 9173.0) + " " + std::to_string(v % 5 - 2));
    s += "Triangles\n" + std::to_string(kTriangles) + "\n";
    for (int f = 0; f < kTriangles; ++f)
      record(f, std::to_string(f + 1) + " " + std::to_string(f + 2),
             std::to_string(f + 3) + " " + std::to_string(f % 7));
    s += "Tetrahedra\n" + std::to_string(kTets) + "\n";
    for (int t = 0; t < kTets; ++t) {
      const int a = t % (kVertices - 3) + 1;
      record(t, std::to_string(a) + " " + std::to_string(a + 1),
             std::to_string(a + 2) + " " + std::to_string(t == bad ? kVertices + 1 : a + 3) + " " +
                 std::to_string(t % 3 + 1));
    }
    return s + "End\n";
  };
  const InputMesh lines = read_input(write_temp("lines.mesh", file(false, -1)));
  const InputMesh free = read_input(write_temp("free.mesh", file(true, -1)));
  ASSERT_EQ(lines.points.size(), size_t{kVertices});
  ASSERT_EQ(lines.tets.size(), size_t{kTets});
  EXPECT_EQ(lines.tets[39999], (std::array<uint32_t, 4>{5, 6, 7, 8}));  // a = 39999 mod 19997 + 1
  for (const InputMesh* m : {&lines, &free}) {
    EXPECT_EQ(m->tets, lines.tets);
    EXPECT_EQ(m->tet_regions, lines.tet_regions);
    EXPECT_EQ(m->tagged_faces, lines.tagged_faces);
    EXPECT_EQ(m->face_tags, lines.face_tags);
    ASSERT_EQ(m->fields.size(), 1u);
    EXPECT_EQ(m->fields[0].values, lines.fields[0].values);
    ASSERT_EQ(m->points.size(), lines.points.size());
    for (size_t i = 0; i < m->points.size(); ++i)
      ASSERT_TRUE(m->points[i].x == lines.points[i].x && m->points[i].y == lines.points[i].y &&
                  m->points[i].z == lines.points[i].z)
          << i;
  }
  EXPECT_EQ(lines.tet_regions[4], 2);
  EXPECT_EQ(lines.face_tags[9], 2);
  // Tetrahedron 30000 is on line 3 + 1 + 20000 + 2 + 3000 + 2 + 30000 + 1.
  const std::string error = read_error("bad.mesh", file(false, 30000));
  EXPECT_NE(error.find("bad.mesh:53009: vertex index 20001 out of range 1..20000"), std::string::npos)
      << error;
}

// A VTK legacy ASCII array is read in pieces on every core, cut between
// values however the lines break them: the same values with nine to a line
// or one, blanks and tabs between; a bad value deep in it is named at its
// line, as one value after another would name it.
TEST(InputFormats, VtkAsciiArraysReadInPiecesWhateverTheLinesAre) {
  constexpr int kPoints = 150000;  // 450,000 coordinates, several pieces
  const auto file = [&](int per_line, const char* blank, int bad) {
    std::string s = "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS " +
                    std::to_string(kPoints) + " double\n";
    for (int i = 0; i < 3 * kPoints; ++i) {
      s += i == bad ? "1.5.5" : std::to_string(i % 1013) + "." + std::to_string(i % 7);
      s += (i + 1) % per_line == 0 ? "\n" : blank;
    }
    return s + "\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\nPOINT_DATA " + std::to_string(kPoints) +
           "\nSCALARS id int 1\nLOOKUP_TABLE default\n" +
           [&] {
             std::string ids;
             for (int i = 0; i < kPoints; ++i) ids += std::to_string(i - 7) + (i % 9 == 8 ? "\n" : " ");
             return ids;
           }() +
           "\n";
  };
  const InputMesh nine = read_input(write_temp("nine.vtk", file(9, " ", -1)));
  const InputMesh one = read_input(write_temp("one.vtk", file(1, " ", -1)));
  const InputMesh tabs = read_input(write_temp("tabs.vtk", file(7, " \t  ", -1)));
  ASSERT_EQ(nine.points.size(), size_t{kPoints});
  EXPECT_EQ(nine.points[100000].y, 300001 % 1013 + (300001 % 7) / 10.0);
  ASSERT_EQ(nine.fields.size(), 1u);
  EXPECT_EQ(nine.fields[0].values[123456], 123456 - 7);
  for (const InputMesh* m : {&one, &tabs}) {
    ASSERT_EQ(m->points.size(), nine.points.size());
    for (size_t i = 0; i < nine.points.size(); ++i)
      ASSERT_TRUE(m->points[i].x == nine.points[i].x && m->points[i].y == nine.points[i].y &&
                  m->points[i].z == nine.points[i].z)
          << i;
    ASSERT_EQ(m->fields.size(), 1u);
    EXPECT_EQ(m->fields[0].values, nine.fields[0].values);
    EXPECT_EQ(m->tets, nine.tets);
  }
  // Value 400,000, nine to a line: line 5 + 1 + 400000 / 9.
  const std::string error = read_error("bad.vtk", file(9, " ", 400000));
  EXPECT_NE(error.find("bad.vtk:44450: expected a number, found '1.5.5'"), std::string::npos) << error;
}

}  // namespace
}  // namespace dtm
