// A second-order mesh's node numbering (format 21.0, spec/FORMAT.md §3.13,
// meshenc --exact --keep-order): level 0 decodes with its vertices and edge
// nodes in the input's numbering, the two kinds interleaved as the file had
// them, each cell naming the same nodes; a mesher's numbering costs less
// than a random one; a numbering that is not one is refused; damaged
// sections are refused or give a numbering, every truncation is refused;
// without the numbering the nodes follow the vertices (20.0).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/sections/edge_node_coder.h"
#include "codec/sections/node_order_coder.h"
#include "codec/stream/format.h"
#include "test_support.h"
#include "tools/decoded_mesh.h"
#include "tools/formats/mesh_writers.h"
#include "tools/formats/tetgen.h"

namespace dtm {
namespace {

using NodePair = std::array<uint32_t, 2>;

NodePair node_pair(uint32_t a, uint32_t b) { return {std::min(a, b), std::max(a, b)}; }

// torus_288 as a second-order mesh numbered as a mesher numbers one: its
// tetrahedra in a shuffled order, each one's corners not yet numbered, then
// its edges' nodes not yet numbered (every fourth node moved off its
// edge's midpoint). `file`: each node of the file, a corner (its index in
// `points`, which hold the corners in the file's order) or an edge node
// (its index in `nodes`, in the file's order); `at`: where each lies.
struct NumberedSecondOrder {
  std::vector<InputPoint> points;
  std::vector<std::array<uint32_t, 4>> tets;  // indices into points
  std::vector<EncodeInput::EdgeNode> nodes;   // corners as indices into points
  std::vector<uint32_t> numbering;            // EncodeInput::node_numbering
  std::vector<InputPoint> at;                 // per file node
  // Per tetrahedron, its corners' and edge nodes' file numbers.
  std::vector<std::array<uint32_t, 4>> file_corners;
  std::vector<std::array<uint32_t, 6>> file_nodes;
};
NumberedSecondOrder numbered_torus(bool random_numbering) {
  const NodeFile node = read_tetgen_node(test::data_path("torus_288.node"));
  const std::vector<std::array<uint32_t, 4>> tets =
      read_tetgen_ele(test::data_path("torus_288.ele"), node.points.size(), node.index_base);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> off(-0.02, 0.02);
  // The file's nodes in a mesher's order: (is an edge node, the corner's
  // index or the edge).
  std::vector<std::pair<bool, NodePair>> order;
  std::set<uint32_t> corners_seen;
  std::set<NodePair> edges_seen;
  std::vector<size_t> visit(tets.size());
  std::iota(visit.begin(), visit.end(), size_t{0});
  std::shuffle(visit.begin(), visit.end(), random);
  for (size_t t : visit) {
    for (uint32_t v : tets[t])
      if (corners_seen.insert(v).second) order.push_back({false, {v, v}});
    for (const auto& [i, j] : kCellEdges)
      if (const NodePair e = node_pair(tets[t][i], tets[t][j]); edges_seen.insert(e).second)
        order.push_back({true, e});
  }
  if (random_numbering) std::shuffle(order.begin(), order.end(), random);
  NumberedSecondOrder m;
  std::map<uint32_t, uint32_t> point_of;  // corner -> index in points
  std::map<NodePair, uint32_t> file_of_edge;
  std::map<uint32_t, uint32_t> file_of_corner;
  // (The points first, so that an edge node can name its corners.)
  for (const auto& [is_node, e] : order)
    if (!is_node) {
      point_of[e[0]] = static_cast<uint32_t>(m.points.size());
      m.points.push_back(node.points[e[0]]);
    }
  uint32_t corner = 0;
  for (const auto& [is_node, e] : order) {
    const auto file = static_cast<uint32_t>(m.at.size());
    if (!is_node) {
      file_of_corner[e[0]] = file;
      m.numbering.push_back(corner++);
      m.at.push_back(node.points[e[0]]);
      continue;
    }
    const InputPoint &a = node.points[e[0]], &b = node.points[e[1]];
    InputPoint p{(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
    if (m.nodes.size() % 4 == 0) p = {p.x + off(random), p.y + off(random), p.z + off(random)};
    file_of_edge[e] = file;
    m.numbering.push_back(static_cast<uint32_t>(m.points.size() + m.nodes.size()));
    m.nodes.push_back({{point_of[e[0]], point_of[e[1]]}, p});
    m.at.push_back(p);
  }
  for (const auto& t : tets) {
    std::array<uint32_t, 4> corners;
    std::array<uint32_t, 6> nodes;
    for (size_t k = 0; k < 4; ++k) corners[k] = file_of_corner[t[k]];
    for (size_t k = 0; k < 6; ++k)
      nodes[k] = file_of_edge[node_pair(t[kCellEdges[k][0]], t[kCellEdges[k][1]])];
    m.tets.push_back({point_of[t[0]], point_of[t[1]], point_of[t[2]], point_of[t[3]]});
    m.file_corners.push_back(corners);
    m.file_nodes.push_back(nodes);
  }
  return m;
}

EncodeOptions exact_numbered_options() {
  EncodeOptions o;
  o.box = 256;
  o.dmax = 2;
  o.exact = true;
  o.keep_order = true;
  return o;
}

StatusOr<EncodedMesh> encode_numbered_torus(const NumberedSecondOrder& m, bool with_numbering,
                                            EncodeOptions o = exact_numbered_options()) {
  EncodeInput in;
  in.points = m.points;
  in.tetrahedra = m.tets;
  in.edge_nodes = m.nodes;
  if (with_numbering) in.node_numbering = m.numbering;
  return encode(in, o);
}

// Each cell as its sorted corners and its edges' nodes, all by number.
using NumberedCell = std::pair<std::array<uint32_t, 4>, std::set<std::pair<NodePair, uint32_t>>>;
NumberedCell numbered_cell(std::array<uint32_t, 4> corners, const std::array<uint32_t, 6>& nodes) {
  NumberedCell c;
  for (size_t k = 0; k < 6; ++k)
    c.second.insert({node_pair(corners[kCellEdges[k][0]], corners[kCellEdges[k][1]]), nodes[k]});
  std::sort(corners.begin(), corners.end());
  c.first = corners;
  return c;
}

TEST(NodeOrder, ASecondOrderMeshComesBackInTheInputsNumbering) {
  const NumberedSecondOrder m = numbered_torus(false);
  const auto encoded = encode_numbered_torus(m, true);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  EXPECT_GT(encoded->report.node_order_bytes, 0u);
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  EXPECT_EQ(d.header().version_major, kVersionMajorExactClosing);
  const OutputMesh mesh = decoded_mesh(d, "numbered", true);
  ASSERT_EQ(mesh.points.size(), m.at.size());
  EXPECT_EQ(mesh.edge_nodes, m.nodes.size());
  // Each node where the file's is (within the corners' rounding: half a
  // step of the stream's grid, mesh.grid's being half of it).
  const double bound = mesh.grid.step * (1 + 1e-9);
  for (size_t k = 0; k < m.at.size(); ++k) {
    const GridPoint& p = mesh.points[k];
    EXPECT_LE(std::abs(mesh.grid.origin[0] + p.x * mesh.grid.step - m.at[k].x), bound) << k;
    EXPECT_LE(std::abs(mesh.grid.origin[1] + p.y * mesh.grid.step - m.at[k].y), bound) << k;
    EXPECT_LE(std::abs(mesh.grid.origin[2] + p.z * mesh.grid.step - m.at[k].z), bound) << k;
  }
  // The same cells, each naming the same numbers.
  std::set<NumberedCell> want, got;
  for (size_t t = 0; t < m.tets.size(); ++t) want.insert(numbered_cell(m.file_corners[t], m.file_nodes[t]));
  ASSERT_EQ(mesh.cell_edge_nodes.size(), mesh.cells.size());
  for (size_t c = 0; c < mesh.cells.size(); ++c)
    got.insert(numbered_cell(mesh.cells[c], mesh.cell_edge_nodes[c]));
  EXPECT_EQ(got, want);
  // A writer of linear cells keeps the corners, in the file's order.
  const OutputMesh linear = without_edge_nodes(mesh);
  ASSERT_EQ(linear.points.size(), m.points.size());
  std::vector<GridPoint> corners;
  for (size_t k = 0; k < m.numbering.size(); ++k)
    if (m.numbering[k] < m.points.size()) corners.push_back(mesh.points[k]);
  EXPECT_EQ(linear.points, corners);
  for (const auto& c : linear.cells)
    for (uint32_t v : c) EXPECT_LT(v, linear.points.size());
}

TEST(NodeOrder, AMeshersNumberingCostsLessThanARandomOne) {
  const auto local = encode_numbered_torus(numbered_torus(false), true);
  const auto random = encode_numbered_torus(numbered_torus(true), true);
  ASSERT_TRUE(local.ok() && random.ok());
  const double nodes = static_cast<double>(numbered_torus(false).nodes.size());
  const double local_bits = 8.0 * static_cast<double>(local->report.node_order_bytes) / nodes;
  const double random_bits = 8.0 * static_cast<double>(random->report.node_order_bytes) / nodes;
  // A random numbering: about log2(nodes) - 1.44 bits a node and a bit
  // for its kind; a mesher's: the next node mostly on the cells around the
  // last one's edge.
  EXPECT_LT(local_bits, 0.75 * random_bits) << local_bits << " against " << random_bits;
  EXPECT_LT(random_bits, std::log2(nodes) + 1.5);
}

TEST(NodeOrder, WithoutTheNumberingTheNodesFollowTheVertices) {
  const NumberedSecondOrder m = numbered_torus(false);
  const auto encoded = encode_numbered_torus(m, false);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  EXPECT_EQ(encoded->report.node_order_bytes, 0u);
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  EXPECT_EQ(d.header().version_major, kVersionMajorExactClosing);
  const OutputMesh mesh = decoded_mesh(d, "after", true);
  for (const auto& e : mesh.cell_edge_nodes)
    for (uint32_t v : e) EXPECT_GE(v, m.points.size());
  for (const auto& c : mesh.cells)
    for (uint32_t v : c) EXPECT_LT(v, m.points.size());
}

TEST(NodeOrder, ANumberingThatIsNotOneIsRefused) {
  const NumberedSecondOrder m = numbered_torus(false);
  const auto refused = [&](std::vector<uint32_t> numbering, EncodeOptions o = exact_numbered_options()) {
    NumberedSecondOrder bad = m;
    bad.numbering = std::move(numbering);
    const auto encoded = encode_numbered_torus(bad, true, o);
    return !encoded.ok() && encoded.status().code() == StatusCode::kInvalidInput;
  };
  std::vector<uint32_t> twice = m.numbering;
  twice.back() = twice[twice.size() - 2];
  EXPECT_TRUE(refused(twice));
  std::vector<uint32_t> short_one(m.numbering.begin(), m.numbering.end() - 1);
  EXPECT_TRUE(refused(short_one));
  std::vector<uint32_t> swapped = m.numbering;
  const auto first_vertex = std::find(swapped.begin(), swapped.end(), 0u);
  const auto second_vertex = std::find(swapped.begin(), swapped.end(), 1u);
  std::iter_swap(first_vertex, second_vertex);
  EXPECT_TRUE(refused(swapped));
  std::vector<uint32_t> past = m.numbering;
  past.back() = static_cast<uint32_t>(m.points.size() + m.nodes.size());
  EXPECT_TRUE(refused(past));
  // Only with the vertex order, and in 21.0's format: otherwise unused,
  // the nodes after the vertices.
  EncodeOptions unordered = exact_numbered_options();
  unordered.keep_order = false;
  const auto without_order = encode_numbered_torus(m, true, unordered);
  ASSERT_TRUE(without_order.ok()) << without_order.status().message();
  EXPECT_EQ(without_order->report.node_order_bytes, 0u);
  EncodeOptions v19 = exact_numbered_options();
  v19.edge_nodes_v19 = true;
  const auto older = encode_numbered_torus(m, true, v19);
  ASSERT_TRUE(older.ok()) << older.status().message();
  EXPECT_EQ(older->report.node_order_bytes, 0u);
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(older->bytes, d).ok());
  EXPECT_EQ(d.header().version_major, kVersionMajorPredictedEdgeNodes);
}

// With the file's own node ids too (22.0): every node's, the edge nodes'
// among the vertices', in the file's order.
TEST(NodeOrder, TheNodesComeBackWithTheirIds) {
  const NumberedSecondOrder m = numbered_torus(false);
  std::vector<int64_t> ids(m.numbering.size());
  for (size_t k = 0; k < ids.size(); ++k) ids[k] = 5 * static_cast<int64_t>(k) + 1 + (k > 100 ? 1000 : 0);
  EncodeInput in;
  in.points = m.points;
  in.tetrahedra = m.tets;
  in.edge_nodes = m.nodes;
  in.node_numbering = m.numbering;
  in.node_labels = ids;
  const auto encoded = encode(in, exact_numbered_options());
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  EXPECT_EQ(d.header().version_major, kVersionMajorExactClosing);
  const OutputMesh mesh = decoded_mesh(d, "ids", true);
  EXPECT_EQ(mesh.node_labels, ids);
  // A writer of linear cells keeps the corners' ids.
  std::vector<int64_t> corner_ids;
  for (size_t k = 0; k < m.numbering.size(); ++k)
    if (m.numbering[k] < m.points.size()) corner_ids.push_back(ids[k]);
  EXPECT_EQ(without_edge_nodes(mesh).node_labels, corner_ids);
  // The nodes' ids without their numbering (an 18.0 or 19.0 stream) are
  // refused by the stream encoder; encode() keeps the numbering's or none.
  EncodeOptions v19 = exact_numbered_options();
  v19.edge_nodes_v19 = true;
  const auto older = encode(in, v19);
  ASSERT_TRUE(older.ok()) << older.status().message();
  EXPECT_EQ(older->report.node_label_bytes, 0u);
}

// Below the layer checksum: a damaged section is refused or names every
// vertex, in order, and every node once; every truncation is refused.
TEST(NodeOrder, DamagedAndTruncatedSectionsAreRefusedOrANumbering) {
  const NumberedSecondOrder m = numbered_torus(false);
  const auto encoded = encode_numbered_torus(m, true);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  const ProgressiveDecoder::EdgeNodes nodes = d.edge_nodes(d.level_cells());
  const std::vector<uint32_t> numbering = d.node_order(nodes);
  ASSERT_TRUE(d.mesh_status().ok()) << d.mesh_status().message();
  const size_t vertices = d.points().size();
  ASSERT_EQ(numbering.size(), vertices + m.nodes.size());
  const NodeOrderFrame frame = node_order_frame(nodes.edges, nodes.present);
  const std::vector<uint8_t> section = encode_node_order(nodes.edges, frame, vertices, numbering);
  std::vector<uint32_t> back;
  ASSERT_TRUE(decode_node_order(section, nodes.edges, frame, vertices, back).ok());
  EXPECT_EQ(back, numbering);
  int refused = 0;
  // (One bit of each byte, a different one from byte to byte: every bit
  // costs seconds and finds no more.)
  for (size_t byte = 0; byte < section.size(); ++byte) {
    {
      std::vector<uint8_t> damaged = section;
      damaged[byte] ^= static_cast<uint8_t>(1 << (byte % 8));
      const Status s = decode_node_order(damaged, nodes.edges, frame, vertices, back);
      if (!s.ok()) {
        EXPECT_EQ(s.code(), StatusCode::kCorrupt);
        ++refused;
        continue;
      }
      ASSERT_EQ(back.size(), numbering.size());
      uint32_t next_vertex = 0;
      std::vector<uint8_t> named(m.nodes.size(), 0);
      for (uint32_t entry : back)
        if (entry < vertices)
          ASSERT_EQ(entry, next_vertex++);
        else
          ASSERT_EQ(named.at(entry - vertices)++, 0);
    }
  }
  EXPECT_GT(refused, 0);
  for (size_t len = 0; len < section.size(); ++len)
    EXPECT_EQ(decode_node_order(std::span(section).first(len), nodes.edges, frame, vertices, back).code(),
              StatusCode::kCorrupt)
        << len;
}

}  // namespace
}  // namespace dtm
