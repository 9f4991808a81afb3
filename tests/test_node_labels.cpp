// The input's node ids (format 22.0, spec/FORMAT.md §3.14, meshenc
// --keep-order of a file that numbers its nodes otherwise than 1 to n):
// the label section codes any ids in range exactly, runs and strides in
// next to nothing, and refuses or decodes a damaged section to valid ids,
// every truncation refused; a mesh keeps them, with its edge nodes too,
// and the gmsh, Abaqus and Exodus writers number their nodes so, which
// the readers read back; a file numbered 1 to n has none, one with ids
// that cannot be kept says so.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/sections/node_label_coder.h"
#include "codec/stream/format.h"
#include "output_mesh_support.h"
#include "test_support.h"
#include "tools/decoded_mesh.h"
#include "tools/formats/input.h"
#include "tools/formats/node_labels.h"
#include "tools/formats/tetgen.h"

namespace dtm {
namespace {

// Ids as meshes number nodes: runs of consecutive ids, a part from its own
// offset, a constant stride, some out of order, one near the top.
std::vector<int64_t> mesher_ids(size_t n) {
  std::vector<int64_t> ids;
  int64_t next = 1000;
  std::mt19937 random(5);
  while (ids.size() < n) {
    const size_t run = 1 + random() % 40;
    const int kind = static_cast<int>(random() % 4);
    for (size_t k = 0; k < run && ids.size() < n; ++k) ids.push_back(next += kind == 3 ? 7 : 1);
    next += kind == 0 ? 100000 : kind == 1 ? 3 : 0;
  }
  std::reverse(ids.begin() + static_cast<std::ptrdiff_t>(n / 3),
               ids.begin() + static_cast<std::ptrdiff_t>(n / 2));
  ids.back() = kMaxNodeLabel;
  return ids;
}

TEST(NodeLabels, TheSectionCodesAnyIdsInRangeAndRunsInNextToNothing) {
  for (const std::vector<int64_t>& ids : {mesher_ids(3000), std::vector<int64_t>{1},
                                          std::vector<int64_t>{kMaxNodeLabel, 1, kMaxNodeLabel - 1}}) {
    ASSERT_TRUE(valid_node_labels(ids));
    std::vector<int64_t> back;
    ASSERT_TRUE(decode_node_labels(encode_node_labels(ids), ids.size(), back).ok());
    EXPECT_EQ(back, ids);
  }
  // A run from an offset, and a constant stride: a few bytes.
  std::vector<int64_t> run(10000), stride(10000);
  std::iota(run.begin(), run.end(), int64_t{500001});
  for (size_t k = 0; k < stride.size(); ++k) stride[k] = 3 * static_cast<int64_t>(k) + 100;
  EXPECT_LT(encode_node_labels(run).size(), 20u);
  EXPECT_LT(encode_node_labels(stride).size(), 20u);
  // Ids the format cannot hold.
  EXPECT_FALSE(valid_node_labels(std::vector<int64_t>{1, 2, 1}));
  EXPECT_FALSE(valid_node_labels(std::vector<int64_t>{0, 1}));
  EXPECT_FALSE(valid_node_labels(std::vector<int64_t>{kMaxNodeLabel + 1}));
}

TEST(NodeLabels, DamagedAndTruncatedSectionsAreRefusedOrValidIds) {
  const std::vector<int64_t> ids = mesher_ids(400);
  const std::vector<uint8_t> section = encode_node_labels(ids);
  std::vector<int64_t> back;
  int refused = 0;
  for (size_t byte = 0; byte < section.size(); ++byte)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> damaged = section;
      damaged[byte] ^= static_cast<uint8_t>(1 << bit);
      const Status s = decode_node_labels(damaged, ids.size(), back);
      if (!s.ok()) {
        EXPECT_EQ(s.code(), StatusCode::kCorrupt);
        ++refused;
        continue;
      }
      ASSERT_EQ(back.size(), ids.size());
      EXPECT_TRUE(valid_node_labels(back));
    }
  EXPECT_GT(refused, 0);
  for (size_t len = 0; len < section.size(); ++len)
    EXPECT_EQ(decode_node_labels(std::span(section).first(len), ids.size(), back).code(),
              StatusCode::kCorrupt)
        << len;
  // A section of more ids than asked for does not end with them.
  EXPECT_EQ(decode_node_labels(section, ids.size() - 1, back).code(), StatusCode::kCorrupt);
}

// torus_288 with the ids of mesher_ids(), kept with --keep-order only.
TEST(NodeLabels, AMeshKeepsItsNodeIdsWithItsOrder) {
  const NodeFile node = read_tetgen_node(test::data_path("torus_288.node"));
  const auto tets = read_tetgen_ele(test::data_path("torus_288.ele"), node.points.size(), node.index_base);
  const std::vector<int64_t> ids = mesher_ids(node.points.size());
  EncodeInput in;
  in.points = node.points;
  in.tetrahedra = tets;
  in.node_labels = ids;
  EncodeOptions o;
  o.box = 256;
  o.dmax = 2;
  o.keep_order = true;
  const auto kept = encode(in, o);
  ASSERT_TRUE(kept.ok()) << kept.status().message();
  EXPECT_GT(kept->report.node_label_bytes, 0u);
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(kept->bytes, d).ok());
  EXPECT_EQ(d.header().version_major, kVersionMajorNodeLabels);
  const OutputMesh mesh = decoded_mesh(d, "labelled");
  EXPECT_EQ(mesh.node_labels, ids);
  // (Without the order the ids name nothing: not kept.)
  o.keep_order = false;
  const auto unordered = encode(in, o);
  ASSERT_TRUE(unordered.ok());
  EXPECT_EQ(unordered->report.node_label_bytes, 0u);
  ProgressiveDecoder plain;
  ASSERT_TRUE(decode_stream(unordered->bytes, plain).ok());
  EXPECT_FALSE(plain.header().flags & kFlagNodeLabels);
  EXPECT_TRUE(decoded_mesh(plain, "plain").node_labels.empty());
  // Ids that are not ids are refused.
  std::vector<int64_t> twice = ids;
  twice[1] = twice[0];
  in.node_labels = twice;
  o.keep_order = true;
  const auto refused = encode(in, o);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.status().code(), StatusCode::kInvalidInput);
}

std::string labelled_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// The writers that name nodes number them with the labels, and the readers
// read them back; a file numbered 1 to n has none.
TEST(NodeLabels, TheGmshAbaqusAndExodusWritersNumberTheNodesSo) {
  OutputMesh m = test::torus_mesh();
  m.node_labels = mesher_ids(m.points.size());
  m.node_labels.back() = 2000000000;  // (Exodus's node map: 32-bit ids here)
  std::vector<MeshFormat> formats = {MeshFormat::kGmsh, MeshFormat::kAbaqus};
#ifdef DTM_WITH_EXODUS
  formats.push_back(MeshFormat::kExodus);
#endif
  const char* const names[] = {"labelled.msh", "labelled.inp", "labelled.e"};
  for (size_t f = 0; f < formats.size(); ++f) {
    const InputMesh back = read_input(test::write(m, formats[f], names[f]));
    EXPECT_EQ(back.node_labels, m.node_labels) << names[f];
    EXPECT_EQ(std::count(back.left_out.begin(), back.left_out.end(), std::string(kNodeIdsNote)), 1)
        << names[f];
    // Each cell names the same nodes by id.
    ASSERT_EQ(back.tets.size(), m.cells.size()) << names[f];
    for (size_t c = 0; c < m.cells.size(); ++c) {
      std::vector<int64_t> want, got;
      for (size_t k = 0; k < 4; ++k) {
        want.push_back(m.node_labels[m.cells[c][k]]);
        got.push_back(back.node_labels[back.tets[c][k]]);
      }
      std::sort(want.begin(), want.end());
      std::sort(got.begin(), got.end());
      ASSERT_EQ(got, want) << names[f] << " cell " << c;
    }
  }
#ifdef DTM_WITH_EXODUS
  OutputMesh huge = m;
  huge.node_labels.back() = kMaxNodeLabel;
  EXPECT_THROW(test::write(huge, MeshFormat::kExodus, "huge.e"), std::invalid_argument);
#endif
  // Numbered 1 to n: no labels, nothing said.
  m.node_labels.clear();
  const InputMesh plain = read_input(test::write(m, MeshFormat::kGmsh, "plain.msh"));
  EXPECT_TRUE(plain.node_labels.empty());
  EXPECT_EQ(std::count(plain.left_out.begin(), plain.left_out.end(), std::string(kNodeIdsNote)), 0);
  // Ids a stream cannot hold (0) are named as left out for good.
  const InputMesh zero = read_input(labelled_file("zero.inp",
                                                  "*NODE\n0, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n"
                                                  "*ELEMENT, TYPE=C3D4\n1, 0, 2, 3, 4\n"));
  EXPECT_TRUE(zero.node_labels.empty());
  EXPECT_TRUE(std::any_of(zero.left_out.begin(), zero.left_out.end(),
                          [](const std::string& s) { return s.rfind("the node ids (not all", 0) == 0; }));
}

}  // namespace
}  // namespace dtm
