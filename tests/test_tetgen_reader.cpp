#include <gtest/gtest.h>

#include <fstream>

#include "test_support.h"
#include "tools/formats/tetgen.h"

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

}  // namespace
}  // namespace dtm
