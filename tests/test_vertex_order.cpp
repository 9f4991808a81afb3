// The input's vertex order (spec/FORMAT.md §3.9, meshenc --keep-order):
// level 0 decodes with its vertices in the input's numbering, whatever the
// numbering; a local numbering costs less than a random one; inputs whose
// points merge are refused; damaged sections are refused or give a
// permutation, every truncation is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/sections/vertex_order_coder.h"
#include "codec/stream/layer_coder.h"
#include "common/csr.h"
#include "core/quantize.h"
#include "mesh/delaunay.h"
#include "test_support.h"
#include "tools/decoded_mesh.h"
#include "tools/formats/tetgen.h"

namespace dtm {
namespace {

using Tet = std::array<uint32_t, 4>;

struct Numbered {
  std::vector<InputPoint> points;
  std::vector<Tet> tets;
  std::vector<double> marker;  // a per-vertex field that names the original point
};

struct Bunny {
  std::vector<InputPoint> points;
  std::vector<Tet> tets;
};
const Bunny& bunny() {
  static const Bunny b = [] {
    const NodeFile node = read_tetgen_node(test::data_path("bunny_10k.node"));
    return Bunny{node.points,
                 read_tetgen_ele(test::data_path("bunny_10k.ele"), node.points.size(), node.index_base)};
  }();
  return b;
}

// bunny_10k with its points renumbered by `order` (new k = old order[k]).
Numbered renumbered(const std::vector<uint32_t>& order) {
  const Bunny& mesh = bunny();
  Numbered out;
  std::vector<uint32_t> new_of_old(order.size());
  for (uint32_t k = 0; k < order.size(); ++k) {
    out.points.push_back(mesh.points[order[k]]);
    out.marker.push_back(order[k]);
    new_of_old[order[k]] = k;
  }
  for (Tet t : mesh.tets) {
    for (uint32_t& v : t) v = new_of_old[v];
    out.tets.push_back(t);
  }
  return out;
}

size_t bunny_points() { return bunny().points.size(); }

StatusOr<EncodedMesh> encode_numbered(const Numbered& in, bool keep_order, int qbits = 14) {
  const std::vector<EncodeInput::Field> fields = {{"original", ValueType::kU32, 1, in.marker}};
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.fields = fields;
  EncodeOptions o;
  o.box = 256;
  o.dmax = 2;
  o.qbits = qbits;
  o.keep_order = keep_order;
  return encode(input, o);
}

TEST(VertexOrder, LevelZeroComesBackInTheInputsNumbering) {
  std::vector<uint32_t> order(bunny_points());
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  const Numbered in = renumbered(order);
  const auto encoded = encode_numbered(in, true);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  ASSERT_GT(encoded->report.order_bytes, 0u);
  ProgressiveDecoder d;
  int levels = 0;
  ASSERT_TRUE(d.feed(encoded->bytes, [&](const ProgressiveDecoder& decoder, const DecodedLevel& level) {
                 ++levels;
                 const OutputMesh m = decoded_mesh(decoder, "bunny");
                 if (level.level != 0) return;  // coarser levels keep the decoder's numbering
                 ASSERT_EQ(m.points.size(), in.points.size());
                 for (size_t k = 0; k < m.points.size(); ++k) {
                   ASSERT_EQ(m.points[k], decoder.points()[encoded->vertex_of_input[k]]) << k;
                   ASSERT_EQ(m.fields[0].bits[k], in.marker[k]) << k;
                 }
                 // The cells name the same points: each input cell that is
                 // a level-0 cell is found with the input's own numbers.
                 std::set<std::array<uint32_t, 4>> cells;
                 for (auto c : m.cells) {
                   std::sort(c.begin(), c.end());
                   cells.insert(c);
                 }
                 size_t found = 0;
                 for (auto t : in.tets) {
                   std::sort(t.begin(), t.end());
                   found += cells.count(t);
                 }
                 EXPECT_GT(found, in.tets.size() * 9 / 10);
               }).ok());
  EXPECT_TRUE(d.finish().ok());
  EXPECT_GE(levels, 3);
  // Without --keep-order the same levels, fewer bytes.
  const auto plain = encode_numbered(in, false);
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain->report.order_bytes, 0u);
  EXPECT_GT(encoded->bytes.size(), plain->bytes.size());
}

// A random numbering costs about log2(n) - 1.44 bits a vertex; a local one
// (the points sorted along a space-filling curve) far less.
TEST(VertexOrder, ALocalNumberingCostsLessThanARandomOne) {
  const size_t n = bunny_points();
  std::vector<uint32_t> random(n);
  std::iota(random.begin(), random.end(), 0u);
  std::shuffle(random.begin(), random.end(), std::mt19937(5));
  const Numbered base = renumbered(random);
  const QuantizedPoints q = quantize(base.points, 14).value();
  std::vector<uint32_t> morton(n);
  std::iota(morton.begin(), morton.end(), 0u);
  std::sort(morton.begin(), morton.end(), [&](uint32_t a, uint32_t b) {
    return morton_encode(q.points[q.input_to_point[a]], 14) <
           morton_encode(q.points[q.input_to_point[b]], 14);
  });
  std::vector<uint32_t> local(n);
  for (size_t k = 0; k < n; ++k) local[k] = random[morton[k]];
  const auto shuffled = encode_numbered(base, true);
  const auto sorted = encode_numbered(renumbered(local), true);
  ASSERT_TRUE(shuffled.ok() && sorted.ok());
  const double random_bits = 8.0 * shuffled->report.order_bytes / n;
  const double local_bits = 8.0 * sorted->report.order_bytes / n;
  EXPECT_LT(random_bits, std::log2(double(n)) - 1.44 + 0.1);
  EXPECT_GT(random_bits, std::log2(double(n)) - 1.44 - 0.5);
  EXPECT_LT(local_bits, 0.6 * random_bits) << local_bits << " vs " << random_bits;
}

TEST(VertexOrder, RefusedWherePointsMergeOrTheStreamCannotCarryIt) {
  std::vector<uint32_t> order(bunny_points());
  std::iota(order.begin(), order.end(), 0u);
  const Numbered in = renumbered(order);
  const auto merged = encode_numbered(in, true, 5);
  ASSERT_FALSE(merged.ok());
  EXPECT_EQ(merged.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(merged.status().message().find("--qbits"), std::string::npos) << merged.status().message();
  EncodeInput input;
  input.points = in.points;
  EncodeOptions paper = EncodeOptions::paper();
  paper.keep_order = true;
  EXPECT_EQ(encode(input, paper).status().code(), StatusCode::kInvalidInput);
  EncodeOptions bricks;
  bricks.bricks = true;
  bricks.keep_order = true;
  EXPECT_EQ(encode(input, bricks).status().code(), StatusCode::kInvalidInput);
}

// Below the layer checksum: a damaged section is refused or names every
// vertex once; every truncation is refused.
TEST(VertexOrder, DamagedAndTruncatedSectionsAreRefusedOrAPermutation) {
  const std::vector<GridPoint> g = test::random_grid_points(300, 8, 4);
  const TetMesh dt = delaunay_tetrahedralize(g).value();
  const Csr neighbours = vertex_neighbours(g.size(), dt.cells);
  std::vector<uint32_t> order(g.size());
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937(6));
  const std::vector<uint8_t> section = encode_vertex_order(neighbours, order);
  std::vector<uint32_t> back;
  ASSERT_TRUE(decode_vertex_order(section, neighbours, back).ok());
  EXPECT_EQ(back, order);
  int refused = 0;
  for (size_t byte = 0; byte < section.size(); ++byte)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> damaged = section;
      damaged[byte] ^= static_cast<uint8_t>(1 << bit);
      const Status s = decode_vertex_order(damaged, neighbours, back);
      if (!s.ok()) {
        EXPECT_EQ(s.code(), StatusCode::kCorrupt);
        ++refused;
        continue;
      }
      std::vector<uint32_t> sorted = back;
      std::sort(sorted.begin(), sorted.end());
      for (uint32_t k = 0; k < sorted.size(); ++k) ASSERT_EQ(sorted[k], k);
    }
  EXPECT_GT(refused, 0);
  for (size_t len = 0; len < section.size(); ++len)
    EXPECT_EQ(decode_vertex_order(std::span(section).first(len), neighbours, back).code(),
              StatusCode::kCorrupt)
        << len;
}

}  // namespace
}  // namespace dtm
