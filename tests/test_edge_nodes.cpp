// The nodes on level 0's edges (format 18.0, codec/sections/edge_node_coder.h,
// spec/FORMAT.md §3.11): an exact stream of a second-order mesh gives each
// edge node back within half a grid step of the input's (a quarter where it
// is moved off its edge's midpoint), an edge of linear cells none; a
// damaged section is refused, never read past; meshdec's writers list them
// as 10-node tetrahedra.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/sections/edge_node_coder.h"
#include "codec/stream/format.h"
#include "test_support.h"
#include "tools/decoded_mesh.h"
#include "tools/formats/tetgen.h"

namespace dtm {
namespace {

using Edge = std::array<uint32_t, 2>;

Edge edge_of(uint32_t a, uint32_t b) { return {std::min(a, b), std::max(a, b)}; }

// torus_288 with a node on every edge of its tetrahedra but those of the
// first `linear` ones (a mesh of linear and second-order cells): at the
// midpoint, or (every third edge) moved off it by up to 0.03 of the
// torus's size, as a curved boundary's are.
struct SecondOrder {
  std::vector<InputPoint> points;
  std::vector<std::array<uint32_t, 4>> tets;
  std::map<Edge, InputPoint> nodes;
  std::set<Edge> moved;
};
SecondOrder second_order_torus(size_t linear) {
  SecondOrder m;
  const NodeFile node = read_tetgen_node(test::data_path("torus_288.node"));
  m.points = node.points;
  m.tets = read_tetgen_ele(test::data_path("torus_288.ele"), node.points.size(), node.index_base);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> off(-0.03, 0.03);
  std::set<Edge> bare;
  for (size_t t = 0; t < linear; ++t)
    for (const auto& [i, j] : kCellEdges) bare.insert(edge_of(m.tets[t][i], m.tets[t][j]));
  for (size_t t = linear; t < m.tets.size(); ++t)
    for (const auto& [i, j] : kCellEdges) {
      const Edge e = edge_of(m.tets[t][i], m.tets[t][j]);
      if (m.nodes.count(e) || bare.count(e)) continue;
      const InputPoint &a = m.points[e[0]], &b = m.points[e[1]];
      InputPoint p{(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
      if (m.nodes.size() % 3 == 0) {
        p = {p.x + off(random), p.y + off(random), p.z + off(random)};
        m.moved.insert(e);
      }
      m.nodes[e] = p;
    }
  return m;
}

// Its nodes as the encoder takes them, and the encoder's input (which
// views them and the mesh).
std::vector<EncodeInput::EdgeNode> nodes_of(const SecondOrder& m) {
  std::vector<EncodeInput::EdgeNode> out;
  for (const auto& [e, p] : m.nodes) out.push_back({e, p});
  return out;
}
EncodeInput input_of(const SecondOrder& m, std::span<const EncodeInput::EdgeNode> nodes) {
  EncodeInput in;
  in.points = m.points;
  in.tetrahedra = m.tets;
  in.edge_nodes = nodes;
  return in;
}

EncodeOptions exact_options() {
  EncodeOptions o;
  o.box = 256;
  o.dmax = 2;
  o.exact = true;
  return o;
}

TEST(EdgeNodes, AnExactSecondOrderMeshGivesBackEachNode) {
  const SecondOrder m = second_order_torus(10);
  const std::vector<EncodeInput::EdgeNode> given = nodes_of(m);
  const EncodeInput in = input_of(m, given);
  const auto encoded = encode(in, exact_options());
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  EXPECT_EQ(encoded->report.edge_nodes, m.nodes.size());
  EXPECT_EQ(encoded->report.moved_edge_nodes, m.moved.size());
  EXPECT_GT(encoded->report.edge_node_bytes, 0u);

  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  EXPECT_EQ(d.header().version_major, kVersionMajorEdgeNodes);
  ASSERT_TRUE(d.has_edge_nodes());
  const ProgressiveDecoder::LevelCells level = d.level_cells();
  const ProgressiveDecoder::EdgeNodes nodes = d.edge_nodes(level);
  ASSERT_TRUE(d.mesh_status().ok()) << d.mesh_status().message();
  std::vector<uint32_t> input_of(d.points().size(), UINT32_MAX);
  for (uint32_t i = 0; i < m.points.size(); ++i) input_of[encoded->vertex_of_input[i]] = i;
  const Grid grid = d.header().grid;
  size_t found = 0;
  for (size_t e = 0; e < nodes.edges.corners.size(); ++e) {
    const Edge edge = edge_of(input_of[nodes.edges.corners[e][0]], input_of[nodes.edges.corners[e][1]]);
    const auto given_node = m.nodes.find(edge);
    ASSERT_EQ(nodes.present[e] != 0, given_node != m.nodes.end()) << e;
    if (!nodes.present[e]) continue;
    ++found;
    // Within half a step of the input's (the corners' rounding), a
    // quarter where the node is coded off the midpoint.
    const double bound = (m.moved.count(edge) ? 0.25 : 0.5) * grid.step * (1 + 1e-9);
    const std::array<double, 3> want = {given_node->second.x, given_node->second.y, given_node->second.z};
    for (size_t axis = 0; axis < 3; ++axis)
      EXPECT_LE(std::abs(grid.origin[axis] + nodes.points[e][axis] * grid.step - want[axis]), bound)
          << "edge " << e << " axis " << axis;
  }
  EXPECT_EQ(found, m.nodes.size());
  // The first ten tetrahedra were linear: their edges have no node.
  EXPECT_LT(found, nodes.edges.corners.size());

  // meshdec's mesh: 10-node tetrahedra where every edge has its node, the
  // coordinates those of the decoder's points (a grid of half the step).
  const OutputMesh out = decoded_mesh(d, "torus", true);
  EXPECT_EQ(out.edge_nodes, m.nodes.size());
  EXPECT_EQ(out.points.size(), m.points.size() + m.nodes.size());
  ASSERT_EQ(out.cell_edge_nodes.size(), out.cells.size());
  size_t second_order = 0;
  for (size_t c = 0; c < out.cells.size(); ++c) {
    const ListedNodes listed = cell_nodes(out, c, kVtkEdgeSlots);
    second_order += listed.second_order();
    for (size_t k = 0; k < 6; ++k) {
      const uint32_t v = out.cell_edge_nodes[c][k];
      if (v == kNoEdgePoint) continue;
      // (The node near its edge's midpoint: the right edge's.)
      const InputPoint a = out.grid.to_input(out.points[out.cells[c][kCellEdges[k][0]]]),
                       b = out.grid.to_input(out.points[out.cells[c][kCellEdges[k][1]]]),
                       p = out.grid.to_input(out.points[v]);
      EXPECT_LT(std::hypot(p.x - (a.x + b.x) / 2, p.y - (a.y + b.y) / 2, p.z - (a.z + b.z) / 2), 0.06);
    }
  }
  EXPECT_GT(second_order, out.cells.size() - 200);
  // An edge node is on the boundary with its edge: both its corners are.
  size_t on_boundary = 0;
  for (size_t c = 0; c < out.cells.size(); ++c)
    for (size_t k = 0; k < 6; ++k)
      if (const uint32_t v = out.cell_edge_nodes[c][k]; v != kNoEdgePoint && out.boundary[v]) {
        ++on_boundary;
        EXPECT_TRUE(out.boundary[out.cells[c][kCellEdges[k][0]]] &&
                    out.boundary[out.cells[c][kCellEdges[k][1]]]);
      }
  EXPECT_GT(on_boundary, 0u);
  EXPECT_LT(second_order, out.cells.size());
  const OutputMesh linear = decoded_mesh(d, "torus");
  EXPECT_EQ(linear.points.size(), m.points.size());
  EXPECT_EQ(linear.cells, out.cells);
  for (size_t v = 0; v < linear.points.size(); ++v)
    EXPECT_EQ(linear.grid.to_input(linear.points[v]).x, out.grid.to_input(out.points[v]).x);
}

TEST(EdgeNodes, OnlyExactStreamsCarryThem) {
  const SecondOrder m = second_order_torus(0);
  const std::vector<EncodeInput::EdgeNode> given = nodes_of(m);
  const EncodeInput in = input_of(m, given);
  // Without --exact they are not level 0's edges: unused, the stream as
  // the linear mesh's.
  EncodeOptions plain = exact_options();
  plain.exact = false;
  const auto without = encode(in, plain);
  ASSERT_TRUE(without.ok());
  EncodeInput linear = in;
  linear.edge_nodes = {};
  EXPECT_EQ(without->bytes, encode(linear, plain)->bytes);
  // Older exact codings cannot carry them.
  EncodeOptions v13 = exact_options();
  v13.exact_ranks = ApexRanks::kAmongFittingInContext;
  EXPECT_FALSE(encode(in, v13).ok());
  // A header that flags them without exact cells, or in a 17.0 stream, is refused.
  const auto with = encode(in, exact_options());
  ASSERT_TRUE(with.ok());
  for (const auto& [flags, major] :
       {std::pair{kFlagEdgeNodes | kFlagCarvingCorrections, kVersionMajorEdgeNodes},
        std::pair{kFlagEdgeNodes | kFlagExact | kFlagCarvingCorrections, uint8_t{17}}}) {
    StreamHeader h;
    ASSERT_TRUE(parse_header(with->bytes, h).ok());
    h.flags = static_cast<uint16_t>(flags);
    h.version_major = major;
    std::vector<uint8_t> bytes = write_header(h);
    bytes.insert(bytes.end(), with->bytes.begin() + static_cast<std::ptrdiff_t>(kHeaderSize),
                 with->bytes.end());
    ProgressiveDecoder d;
    EXPECT_FALSE(d.feed(bytes).ok()) << flags << " " << int{major};
  }
}

// The section alone over a decoded level's edges: every truncation is
// refused, and a flipped bit is refused or gives nodes whose section
// decodes to them again.
TEST(EdgeNodes, DamagedSectionsAreRefused) {
  const SecondOrder m = second_order_torus(0);
  const std::vector<EncodeInput::EdgeNode> given = nodes_of(m);
  const EncodeInput in = input_of(m, given);
  const auto encoded = encode(in, exact_options());
  ASSERT_TRUE(encoded.ok());
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  const ProgressiveDecoder::LevelCells level = d.level_cells();
  const LevelEdges edges = level_edges(level.mesh, level.kept, level.order);
  const int qbits = d.header().grid.qbits;
  // The section is the stream's last bytes.
  const std::vector<uint8_t> section(
      encoded->bytes.end() - static_cast<std::ptrdiff_t>(encoded->report.edge_node_bytes),
      encoded->bytes.end());
  EdgeNodeOffsets nodes;
  ASSERT_TRUE(decode_edge_nodes(section, edges, qbits, nodes).ok());
  EXPECT_EQ(encode_edge_nodes(edges, nodes, qbits), section);
  for (size_t n = 0; n < section.size(); ++n) {
    EdgeNodeOffsets cut;
    EXPECT_FALSE(decode_edge_nodes(std::span(section).first(n), edges, qbits, cut).ok()) << n;
  }
  // (The first 64 bytes' bits, and every 13th byte's after: each decode
  // reads the whole section.)
  size_t refused = 0, flipped = 0;
  for (size_t i = 0; i < section.size(); i += i < 64 ? 1 : 13)
    for (int b = 0; b < 8; ++b) {
      std::vector<uint8_t> damaged = section;
      damaged[i] ^= static_cast<uint8_t>(1 << b);
      ++flipped;
      EdgeNodeOffsets got;
      if (!decode_edge_nodes(damaged, edges, qbits, got).ok()) {
        ++refused;
        continue;
      }
      EdgeNodeOffsets again;
      ASSERT_TRUE(decode_edge_nodes(encode_edge_nodes(edges, got, qbits), edges, qbits, again).ok());
      EXPECT_EQ(again.present, got.present);
      EXPECT_EQ(again.offset, got.offset);
    }
  EXPECT_GT(refused, flipped / 2);
}

}  // namespace
}  // namespace dtm
