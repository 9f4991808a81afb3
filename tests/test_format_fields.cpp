// The header tables of spec/FORMAT.md (§2 and §3) against the field lists of
// codec/stream/format.h, from which the writer, the parser and the sizes derive:
// the spec and the code describe the same bytes.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "codec/stream/format.h"

namespace dtm {
namespace {

struct Row {
  size_t offset = 0, size = 0;
  std::string type, field;
};

// Collects the rows a field list makes, typed as the spec writes them.
struct RowCollector {
  std::vector<Row> rows;
  size_t at = 0;
  void add(const char* name, size_t size, std::string type) {
    rows.push_back({at, size, std::move(type), name});
    at += size;
  }
  template <class Wire>
  static std::string type_of() {
    if (std::is_same_v<Wire, double>) return "f64";
    return "u" + std::to_string(8 * sizeof(Wire));
  }
  void magic(const char* name) { add(name, kMagic.size(), "bytes"); }
  template <class Wire, class T>
  void field(const char* name, const T&) {
    add(name, sizeof(Wire), type_of<Wire>());
  }
  template <class Wire, class T, size_t N>
  void field(const char* name, const std::array<T, N>&) {
    add(name, N * sizeof(Wire), std::to_string(N) + " × " + type_of<Wire>());
  }
  template <class Wire, class T>
  void checksum(const char* name, const T& v) {
    field<Wire>(name, v);
  }
};

// The rows with a numeric size of the first table after `heading`.
std::vector<Row> spec_table(const std::string& heading) {
  std::ifstream in(std::string(DTM_TEST_SOURCE_DIR) + "/../spec/FORMAT.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string spec = text.str();
  const size_t start = spec.find(heading);
  EXPECT_NE(start, std::string::npos) << heading;
  std::istringstream lines(spec.substr(start));
  const std::regex row(R"(^\| (\d+) \| (\d+) \| ([^|]+?) \| ([^|]+?) \|$)");
  std::vector<Row> rows;
  bool in_table = false;
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, row)) {
      rows.push_back({std::stoul(m[1]), std::stoul(m[2]), m[3], m[4]});
      in_table = true;
    } else if (in_table && line.rfind("|", 0) != 0) {
      break;
    }
  }
  return rows;
}

template <class Header>
void expect_spec_matches(const std::string& heading, Header h = {}) {
  RowCollector code;
  visit_fields(h, code);
  const std::vector<Row> spec = spec_table(heading);
  ASSERT_EQ(spec.size(), code.rows.size()) << heading;
  for (size_t i = 0; i < spec.size(); ++i) {
    EXPECT_EQ(spec[i].offset, code.rows[i].offset) << code.rows[i].field;
    EXPECT_EQ(spec[i].size, code.rows[i].size) << code.rows[i].field;
    EXPECT_EQ(spec[i].type, code.rows[i].type) << code.rows[i].field;
    // The spec may say more after the name ("magic = 89 44 ...").
    EXPECT_EQ(spec[i].field.substr(0, spec[i].field.find(' ')), code.rows[i].field);
  }
}

TEST(FormatFields, StreamHeaderTableIsTheCodesFieldList) {
  expect_spec_matches<StreamHeader>("## 2. Header");
}

// (The table is level 0's layer of a stream with every section's flag.)
TEST(FormatFields, LayerHeaderTableIsTheCodesFieldList) {
  LayerHeader h;
  h.stream_flags = kFlagValues | kFlagRegions | kFlagFaces | kFlagCellData | kFlagVertexOrder | kFlagExact |
                   kFlagEdgeNodes | kFlagNodeLabels;
  h.level = 0;
  expect_spec_matches<LayerHeader>("## 3. Layer", h);
}

TEST(FormatFields, ChecksumsCoverTheBytesBeforeThem) {
  EXPECT_EQ(sized<StreamHeader>().checksum_offset + 4, kHeaderSize);
  EXPECT_EQ(sized<LayerHeader>(kVersionMajorNodeLabels).checksum_offset + 8,
            layer_header_size(kVersionMajorNodeLabels));
  // 23.0: the lengths the flags call for, level 0's own in level 0 alone.
  for (const uint16_t flags : {0, kFlagValues | kFlagExact,
                               kFlagValues | kFlagExact | kFlagEdgeNodes | kFlagVertexOrder |
                                   kFlagNodeLabels | kFlagRegions | kFlagFaces | kFlagCellData})
    for (const uint16_t level : {0, 1})
      EXPECT_EQ(sized<LayerHeader>(kVersionMajorLayerSizesByFlags, false, flags, level).checksum_offset + 8,
                layer_header_size(kVersionMajorLayerSizesByFlags, false, flags, level));
  EXPECT_EQ(layer_header_size(kVersionMajorLayerSizesByFlags, false,
                              kFlagValues | kFlagExact | kFlagEdgeNodes | kFlagVertexOrder | kFlagNodeLabels |
                                  kFlagRegions | kFlagFaces | kFlagCellData,
                              0),
            layer_header_size(kVersionMajorNodeLabels));
  EXPECT_EQ(
      layer_header_size(kVersionMajorLayerSizesByFlags, false, kFlagRegions | kFlagFaces | kFlagExact, 1),
      layer_header_size(kVersionMajorLayerSizesByFlags) + 8);
  EXPECT_EQ(sized<LayerHeader>(kVersionMajorNodeOrder).checksum_offset + 8,
            layer_header_size(kVersionMajorNodeOrder));
  EXPECT_EQ(sized<LayerHeader>(kVersionMajorPredictedEdgeNodes).checksum_offset + 8,
            layer_header_size(kVersionMajorPredictedEdgeNodes));
  EXPECT_EQ(sized<LayerHeader>(kVersionMajorEdgeNodes).checksum_offset + 8,
            layer_header_size(kVersionMajorEdgeNodes));
  EXPECT_EQ(sized<LayerHeader>(kVersionMajorExact).checksum_offset + 8,
            layer_header_size(kVersionMajorExact));
  EXPECT_EQ(sized<LayerHeader>(kVersionMajorRegions).checksum_offset + 8, kRegionLayerHeaderSize);
  EXPECT_EQ(sized<LayerHeader>(kVersionMajorUnbricked).checksum_offset + 8, kLayerHeaderSize);
}

}  // namespace
}  // namespace dtm
