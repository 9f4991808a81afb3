// The nodes on level 0's edges (format 18.0, 19.0: predicted; codec/sections/edge_node_coder.h,
// spec/FORMAT.md §3.11): an exact stream of a second-order mesh gives each
// edge node back within half a grid step of the input's (a quarter where it
// is moved off its edge's midpoint), an edge of linear cells none; with
// fields, each node's values (19.0, §3.12) as a vertex's, lossless or
// within the bound; a damaged section is refused, never read past;
// meshdec's writers list them as 10-node tetrahedra.
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
#include "codec/sections/face_coder.h"
#include "codec/stream/format.h"
#include "codec/stream/format_encoder.h"
#include "common/byte_io.h"
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
  EXPECT_EQ(d.header().version_major, kVersionMajorExactClosing);
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
  // 18.0's offsets, 19.0's differences from the predicted ones, and
  // 20.0's (the creases apart).
  for (const uint8_t major :
       {kVersionMajorEdgeNodes, kVersionMajorPredictedEdgeNodes, kVersionMajorCreaseEdgeNodes}) {
    EncodeOptions options = exact_options();
    options.edge_nodes_v18 = major == kVersionMajorEdgeNodes;
    options.edge_nodes_v19 = major == kVersionMajorPredictedEdgeNodes;
    const auto encoded = encode(in, options);
    ASSERT_TRUE(encoded.ok());
    ProgressiveDecoder d;
    ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
    // (20.0's nodes come in the exact streams of 23.0.)
    EXPECT_EQ(d.header().version_major,
              major == kVersionMajorCreaseEdgeNodes ? kVersionMajorExactClosing : major);
    const ProgressiveDecoder::LevelCells level = d.level_cells();
    const LevelEdges edges = level_edges(level.mesh, level.kept, level.order);
    const int qbits = d.header().grid.qbits;
    std::optional<EdgeNodePredictor> predictor;
    if (major >= kVersionMajorPredictedEdgeNodes)
      predictor.emplace(level.mesh, level.kept, d.points(), qbits, major >= kVersionMajorCreaseEdgeNodes);
    const EdgeNodePredictor* predicted = predictor ? &*predictor : nullptr;
    // The section is the stream's last bytes.
    const std::vector<uint8_t> section(
        encoded->bytes.end() - static_cast<std::ptrdiff_t>(encoded->report.edge_node_bytes),
        encoded->bytes.end());
    EdgeNodeOffsets nodes;
    ASSERT_TRUE(decode_edge_nodes(section, edges, qbits, nodes, predicted).ok());
    EXPECT_EQ(encode_edge_nodes(edges, nodes, qbits, predicted), section);
    for (size_t n = 0; n < section.size(); ++n) {
      EdgeNodeOffsets cut;
      EXPECT_FALSE(decode_edge_nodes(std::span(section).first(n), edges, qbits, cut, predicted).ok()) << n;
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
        if (!decode_edge_nodes(damaged, edges, qbits, got, predicted).ok()) {
          ++refused;
          continue;
        }
        EdgeNodeOffsets again;
        ASSERT_TRUE(
            decode_edge_nodes(encode_edge_nodes(edges, got, qbits, predicted), edges, qbits, again, predicted)
                .ok());
        EXPECT_EQ(again.present, got.present);
        EXPECT_EQ(again.offset, got.offset);
      }
    EXPECT_GT(refused, flipped / 2) << int{major};
  }
}

// 19.0's prediction against the formula in doubles (spec/FORMAT.md §3.11):
// on the torus's level 0 cut into two regions (so that the surface has an
// interface too), each surface edge's predicted offset is within a half
// step of -(((b - a) . n_a) n_a + ((a - b) . n_b) n_b) / 4, n_v the unit
// sum of v's surface faces' normals, each turned out of its cell.
TEST(EdgeNodes, ThePredictionIsACurvedTrianglesEdgeMidpoint) {
  const SecondOrder m = second_order_torus(0);
  const std::vector<EncodeInput::EdgeNode> given = nodes_of(m);
  const auto encoded = encode(input_of(m, given), exact_options());
  ASSERT_TRUE(encoded.ok());
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  const ProgressiveDecoder::LevelCells level = d.level_cells();
  const std::vector<GridPoint>& p = d.points();
  const auto at = [&](uint32_t v) {
    return std::array<double, 3>{double(p[v].x), double(p[v].y), double(p[v].z)};
  };
  std::vector<uint8_t> kept(level.kept.size(), 0);
  for (size_t c = 0; c < kept.size(); ++c)
    if (level.kept[c]) kept[c] = at(level.mesh.cells[c][0])[0] < (1 << 13) ? 1 : 2;
  const EdgeNodePredictor predictor(level.mesh, kept, p, d.header().grid.qbits, false);
  const LevelEdges edges = level_edges(level.mesh, kept, level.order);
  std::vector<std::array<double, 3>> normal(p.size(), {0, 0, 0});
  for (const SurfaceFace& f : surface_faces(level.mesh, kept).faces) {
    const auto a = at(f.key[0]), b = at(f.key[1]), c = at(f.key[2]);
    std::array<double, 3> centroid{0, 0, 0};
    for (uint32_t v : level.mesh.cells[f.cell])
      for (size_t i = 0; i < 3; ++i) centroid[i] += at(v)[i] / 4;
    std::array<double, 3> n = {(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                               (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                               (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])};
    double inward = 0;
    for (size_t i = 0; i < 3; ++i) inward += n[i] * (centroid[i] - a[i]);
    for (uint32_t v : f.key)
      for (size_t i = 0; i < 3; ++i) normal[v][i] += inward > 0 ? -n[i] : n[i];
  }
  size_t surface = 0, bulging = 0;
  for (size_t e = 0; e < edges.corners.size(); ++e) {
    const uint32_t a = edges.corners[e][0], b = edges.corners[e][1];
    const std::array<int64_t, 3> got = predictor.offset(a, b);
    if (!edges.on_surface[e]) continue;
    ++surface;
    std::array<double, 3> want{0, 0, 0};
    for (const auto& [v, w] : {std::pair{a, b}, std::pair{b, a}}) {
      const double length = std::hypot(normal[v][0], normal[v][1], normal[v][2]);
      double dot = 0;
      for (size_t i = 0; i < 3; ++i) dot += (at(w)[i] - at(v)[i]) * normal[v][i] / length;
      for (size_t i = 0; i < 3; ++i) want[i] -= dot * normal[v][i] / length / 4;
    }
    for (size_t i = 0; i < 3; ++i) EXPECT_LE(std::abs(double(got[i]) - want[i]), 0.5 + 1e-3) << e << " " << i;
    bulging += std::abs(got[0]) + std::abs(got[1]) + std::abs(got[2]) >= 4;
  }
  EXPECT_GT(surface, 500u);
  EXPECT_GT(bulging, surface / 4);
}

// 20.0's prediction against the same formulas in doubles, the surface's
// creases apart (spec/FORMAT.md §3.11): on the two-region torus (whose
// interface meets the boundary along edges of three surface faces), a
// crease edge's offset is within a half step of |d| (t_a - t_b) / 4, t_v
// the unit tangent along the crease (from v's other crease neighbour c
// past it, b - c at a and c - a at b, or the edge's own where v has other
// than two crease edges or the crease turns there by more than 60
// degrees); any other surface edge's of the curved triangle's, each
// corner's normal the unit sum of its faces on the edge's side of the
// creases about it.
TEST(EdgeNodes, TwentyPredictsWithTheCreasesApart) {
  const SecondOrder m = second_order_torus(0);
  const std::vector<EncodeInput::EdgeNode> given = nodes_of(m);
  const auto encoded = encode(input_of(m, given), exact_options());
  ASSERT_TRUE(encoded.ok());
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  const ProgressiveDecoder::LevelCells level = d.level_cells();
  const std::vector<GridPoint>& p = d.points();
  using V = std::array<double, 3>;
  const auto at = [&](uint32_t v) { return V{double(p[v].x), double(p[v].y), double(p[v].z)}; };
  const auto sub = [](const V& a, const V& b) { return V{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  const auto dot = [](const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  const auto cosine = [&](const V& a, const V& b) { return dot(a, b) / std::sqrt(dot(a, a) * dot(b, b)); };
  std::vector<uint8_t> kept(level.kept.size(), 0);
  for (size_t c = 0; c < kept.size(); ++c)
    if (level.kept[c]) kept[c] = at(level.mesh.cells[c][0])[0] < (1 << 13) ? 1 : 2;
  const EdgeNodePredictor predictor(level.mesh, kept, p, d.header().grid.qbits, true);
  const LevelEdges edges = level_edges(level.mesh, kept, level.order);
  // The surface's faces, each turned out of its cell, by edge and by vertex.
  std::vector<std::pair<std::array<uint32_t, 3>, V>> faces;
  std::map<std::pair<uint32_t, uint32_t>, std::vector<size_t>> on_edge;
  std::map<uint32_t, std::vector<size_t>> at_vertex;
  for (const SurfaceFace& f : surface_faces(level.mesh, kept).faces) {
    const V a = at(f.key[0]), u = sub(at(f.key[1]), a), v = sub(at(f.key[2]), a);
    V n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    if (dot(n, sub(at(level.mesh.cells[f.cell][f.opposite]), a)) > 0) n = {-n[0], -n[1], -n[2]};
    for (size_t k = 0; k < 3; ++k) {
      const uint32_t x = f.key[k], y = f.key[(k + 1) % 3];
      on_edge[{std::min(x, y), std::max(x, y)}].push_back(faces.size());
      at_vertex[x].push_back(faces.size());
    }
    faces.push_back({f.key, n});
  }
  // (An angle within 1e-4 of 60 degrees could go either way: an edge whose
  // prediction meets one is not compared.)
  std::set<std::pair<uint32_t, uint32_t>> unclear_edges;
  bool unclear = false;
  const auto crease = [&](uint32_t a, uint32_t b) {
    const auto& f = on_edge.at({std::min(a, b), std::max(a, b)});
    if (f.size() != 2) return true;
    const double c = cosine(faces[f[0]].second, faces[f[1]].second);
    if (std::abs(c - 0.5) < 1e-4) unclear = true, unclear_edges.insert({std::min(a, b), std::max(a, b)});
    return c < 0.5;
  };
  std::map<uint32_t, std::vector<uint32_t>> crease_ends;
  for (const auto& [e, f] : on_edge)
    if (crease(e.first, e.second))
      crease_ends[e.first].push_back(e.second), crease_ends[e.second].push_back(e.first);
  // v's normal on the side of its faces that the face `start` is on.
  const auto sector_normal = [&](uint32_t v, size_t start) {
    std::set<size_t> seen = {start};
    std::vector<size_t> todo = {start};
    V n = {0, 0, 0};
    while (!todo.empty()) {
      const size_t f = todo.back();
      todo.pop_back();
      for (size_t i = 0; i < 3; ++i) n[i] += faces[f].second[i];
      for (uint32_t w : faces[f].first)
        if (w != v && !crease(v, w))
          for (size_t g : on_edge.at({std::min(v, w), std::max(v, w)}))
            if (seen.insert(g).second) todo.push_back(g);
    }
    const double length = std::sqrt(dot(n, n));
    return V{n[0] / length, n[1] / length, n[2] / length};
  };
  size_t creases = 0, smooth = 0, bulging = 0;
  for (size_t e = 0; e < edges.corners.size(); ++e) {
    if (!edges.on_surface[e]) continue;
    const uint32_t a = edges.corners[e][0], b = edges.corners[e][1];
    const std::array<int64_t, 3> got = predictor.offset(a, b);
    unclear = false;
    const V d = sub(at(b), at(a));
    V want{0, 0, 0};
    if (crease(a, b)) {
      ++creases;
      const auto tangent = [&](uint32_t v, uint32_t other, bool at_a) {
        const auto& ends = crease_ends.at(v);
        if (ends.size() != 2) return d;
        const uint32_t c = ends[0] == other ? ends[1] : ends[0];
        const V in = at_a ? sub(at(v), at(c)) : d, out = at_a ? d : sub(at(c), at(v));
        if (std::abs(cosine(in, out) - 0.5) < 1e-4) unclear = true, unclear_edges.insert({a, b});
        if (cosine(in, out) < 0.5) return d;
        return at_a ? sub(at(other), at(c)) : sub(at(c), at(other));
      };
      const V ta = tangent(a, b, true), tb = tangent(b, a, false);
      const double length = std::sqrt(dot(d, d)), la = std::sqrt(dot(ta, ta)), lb = std::sqrt(dot(tb, tb));
      for (size_t i = 0; i < 3; ++i) want[i] = length * (ta[i] / la - tb[i] / lb) / 4;
    } else {
      ++smooth;
      const size_t f = on_edge.at({a, b})[0];
      for (const auto& [v, w] : {std::pair{a, b}, std::pair{b, a}}) {
        const V n = sector_normal(v, f);
        const double along = dot(sub(at(w), at(v)), n);
        for (size_t i = 0; i < 3; ++i) want[i] -= along * n[i] / 4;
      }
    }
    if (unclear) continue;
    for (size_t i = 0; i < 3; ++i) EXPECT_LE(std::abs(double(got[i]) - want[i]), 0.5 + 1e-3) << e << " " << i;
    bulging += std::abs(got[0]) + std::abs(got[1]) + std::abs(got[2]) >= 4;
  }
  EXPECT_GT(creases, 50u);
  EXPECT_GT(smooth, 500u);
  EXPECT_GT(bulging, (creases + smooth) / 4);
  EXPECT_LT(unclear_edges.size(), (creases + smooth) / 100);
}

// 20.0's integers on one tetrahedron, as a reimplementation of §3.11 from
// the spec alone computes them: its faces at the edge (0, 1) part by
// exactly 60 degrees (outward normals along (1, 1, 0) and (1, 0, 1), whose
// 4 (u.v)^2 equals |u|^2 |v|^2: not a crease), so that corners 0 and 1 have
// two crease edges each and the crease edges (0, 2) and (0, 3) take a
// tangent from the crease's next vertex at one end and the edge's own
// where the crease turns sharply at the other; with corner 3 moved, every
// edge is a crease, every corner has three, and no node is expected off
// its edge's midpoint.
TEST(EdgeNodes, TwentyOnATetrahedronAtSixtyDegrees) {
  TetMesh mesh;
  mesh.cells = {{0, 1, 2, 3}};
  mesh.neighbors = {{-1, -1, -1, -1}};
  const std::vector<uint8_t> kept = {1};
  const std::vector<GridPoint> at_sixty = {
      {10000, 10000, 10000}, {14000, 6000, 6000}, {12000, 8000, 15000}, {13000, 15000, 7000}};
  const EdgeNodePredictor sixty(mesh, kept, at_sixty, 14, true);
  using Offset = std::array<int64_t, 3>;
  EXPECT_EQ(sixty.offset(0, 1), (Offset{0, 0, 0}));
  EXPECT_EQ(sixty.offset(0, 2), (Offset{-635, -442, -174}));
  EXPECT_EQ(sixty.offset(0, 3), (Offset{-596, -175, -478}));
  EXPECT_EQ(sixty.offset(1, 2), (Offset{0, 0, 0}));
  EXPECT_EQ(sixty.offset(1, 3), (Offset{0, 0, 0}));
  EXPECT_EQ(sixty.offset(2, 3), (Offset{0, 0, 0}));
  std::vector<GridPoint> moved = at_sixty;
  moved[3].z = 8000;
  const EdgeNodePredictor creases(mesh, kept, moved, 14, true);
  for (const auto& [a, b] : {std::pair{0u, 1u}, {0u, 2u}, {0u, 3u}, {1u, 2u}, {1u, 3u}, {2u, 3u}})
    EXPECT_EQ(creases.offset(a, b), (Offset{0, 0, 0})) << a << " " << b;
}

// Fields at the nodes (19.0): a smooth float64 field and an int32 one
// given at every node, a lossy float32 one, and one given at the vertices
// alone (each node gets its edge's corners' mean).
struct NodeFields {
  std::vector<std::vector<double>> at_points, at_nodes;
  std::vector<EncodeInput::Field> fields;
};
double smooth(const InputPoint& p, int component) { return std::sin(3 * p.x + component) + p.y * p.z; }
NodeFields fields_of(const SecondOrder& m, std::span<const EncodeInput::EdgeNode> nodes) {
  NodeFields f;
  f.at_points.resize(4), f.at_nodes.resize(4);
  for (size_t i = 0; i < m.points.size(); ++i) {
    f.at_points[0].push_back(smooth(m.points[i], 0));
    f.at_points[1].push_back(static_cast<double>(i % 7));
    for (int c = 0; c < 2; ++c) f.at_points[2].push_back(static_cast<float>(smooth(m.points[i], c + 1)));
    f.at_points[3].push_back(smooth(m.points[i], 5));
  }
  for (size_t k = 0; k < nodes.size(); ++k) {
    f.at_nodes[0].push_back(smooth(nodes[k].at, 0));
    f.at_nodes[1].push_back(static_cast<double>(k % 5));
    for (int c = 0; c < 2; ++c) f.at_nodes[2].push_back(static_cast<float>(smooth(nodes[k].at, c + 1)));
  }
  f.fields = {{"smooth", ValueType::kF64, 1, f.at_points[0], f.at_nodes[0]},
              {"label", ValueType::kI32, 1, f.at_points[1], f.at_nodes[1]},
              {"lossy", ValueType::kF32, 2, f.at_points[2], f.at_nodes[2]},
              {"vertices only", ValueType::kF64, 1, f.at_points[3], {}}};
  return f;
}
EncodeOptions fields_options() {
  EncodeOptions o = exact_options();
  o.field_errors["lossy"] = 1e-3;
  return o;
}

// The torus with its nodes (its first `linear` cells linear) and
// fields_of()'s fields, as the encoder takes them: `in` views the others.
struct TorusWithFields {
  explicit TorusWithFields(size_t linear)
      : m(second_order_torus(linear)), given(nodes_of(m)), f(fields_of(m, given)), in(input_of(m, given)) {
    in.fields = f.fields;
  }
  TorusWithFields(const TorusWithFields&) = delete;
  TorusWithFields& operator=(const TorusWithFields&) = delete;
  SecondOrder m;
  std::vector<EncodeInput::EdgeNode> given;
  NodeFields f;
  EncodeInput in;
};

TEST(EdgeNodes, TheFieldsValuesAtTheNodesComeBack) {
  const TorusWithFields torus(10);
  const auto& [m, given, f, in] = torus;
  const auto encoded = encode(in, fields_options());
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  EXPECT_GT(encoded->report.edge_value_bytes, 0u);
  ASSERT_EQ(encoded->report.fields.size(), 4u);
  // A smooth field's nodes cost less than its vertices (predicted from
  // their edge's corners).
  EXPECT_LT(encoded->report.fields[2].edge_value_bytes * m.points.size(),
            encoded->report.fields[2].bytes * m.nodes.size());

  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  EXPECT_EQ(d.header().version_major, kVersionMajorExactClosing);
  const ProgressiveDecoder::LevelCells level = d.level_cells();
  const ProgressiveDecoder::EdgeNodes nodes = d.edge_nodes(level);
  ASSERT_TRUE(d.mesh_status().ok()) << d.mesh_status().message();
  ASSERT_EQ(nodes.values.size(), 4u);
  std::vector<uint32_t> input_of(d.points().size(), UINT32_MAX);
  for (uint32_t i = 0; i < m.points.size(); ++i) input_of[encoded->vertex_of_input[i]] = i;
  std::map<Edge, size_t> given_index;
  for (size_t k = 0; k < given.size(); ++k)
    given_index[edge_of(given[k].corners[0], given[k].corners[1])] = k;
  size_t n = 0;  // the node's rank among the present
  for (size_t e = 0; e < nodes.edges.corners.size(); ++e) {
    if (!nodes.present[e]) continue;
    const uint32_t a = input_of[nodes.edges.corners[e][0]], b = input_of[nodes.edges.corners[e][1]];
    const size_t k = given_index.at(edge_of(a, b));
    EXPECT_EQ(nodes.values[0].value(n, 0), f.at_nodes[0][k]) << e;  // lossless: the same double
    EXPECT_EQ(nodes.values[1].value(n, 0), f.at_nodes[1][k]) << e;
    for (int c = 0; c < 2; ++c)
      EXPECT_LE(std::abs(nodes.values[2].value(n, c) - f.at_nodes[2][k * 2 + static_cast<size_t>(c)]),
                1e-3 * (1 + 1e-6))
          << e;
    EXPECT_EQ(nodes.values[3].value(n, 0), (f.at_points[3][a] + f.at_points[3][b]) / 2) << e;
    ++n;
  }
  EXPECT_EQ(n, m.nodes.size());
  // meshdec's mesh holds them at the nodes' points.
  const OutputMesh out = decoded_mesh(d, "torus", true);
  ASSERT_EQ(out.fields.size(), 4u);
  const size_t base = out.points.size() - out.edge_nodes;
  for (size_t k = 0; k < out.edge_nodes; ++k) {
    EXPECT_EQ(out.fields[0].bits[base + k], nodes.values[0].bits[k]);
    EXPECT_EQ(out.fields[2].bits[2 * (base + k) + 1], nodes.values[2].bits[2 * k + 1]);
  }

  // With the input's numbering (--keep-order) too: each cell's nodes, named
  // by the input's corners, hold the input's values.
  EncodeOptions ordered = fields_options();
  ordered.keep_order = true;
  const auto kept = encode(in, ordered);
  ASSERT_TRUE(kept.ok()) << kept.status().message();
  ProgressiveDecoder k;
  {
    const Status st = decode_stream(kept->bytes, k);
    ASSERT_TRUE(st.ok()) << st.message();
  }
  const OutputMesh numbered = decoded_mesh(k, "torus", true);
  size_t checked = 0;
  for (size_t c = 0; c < numbered.cells.size(); ++c)
    for (size_t e = 0; e < 6; ++e) {
      const uint32_t v = numbered.cell_edge_nodes[c][e];
      if (v == kNoEdgePoint) continue;
      const size_t node =
          given_index.at(edge_of(numbered.cells[c][kCellEdges[e][0]], numbered.cells[c][kCellEdges[e][1]]));
      EXPECT_EQ(value_of(numbered.fields[0].bits[v], ValueType::kF64), f.at_nodes[0][node]);
      EXPECT_EQ(value_of(numbered.fields[1].bits[v], ValueType::kI32), f.at_nodes[1][node]);
      ++checked;
    }
  EXPECT_GT(checked, m.nodes.size());
}

// A stream with its edge value section taken out, or kept in a layer of an
// older version, as a function of the stream's bytes: its header with
// `major`, each layer re-written with `major`'s fields and without an edge
// value section where `drop` says so.
std::vector<uint8_t> restreamed(std::span<const uint8_t> bytes, uint8_t major, bool drop) {
  StreamHeader h;
  EXPECT_TRUE(parse_header(bytes, h).ok());
  std::vector<FieldDescription> fields;
  size_t table = 0;
  EXPECT_TRUE(parse_field_table(bytes.subspan(kHeaderSize), fields, table).ok());
  LayerWalk walk(h, UINT64_MAX, table);
  h.version_major = major;
  std::vector<uint8_t> out = write_header(h);
  out.insert(out.end(), bytes.begin() + kHeaderSize,
             bytes.begin() + static_cast<std::ptrdiff_t>(kHeaderSize + table));
  Layer l;
  while (walk.next(bytes.subspan(walk.offset()), l).ok()) {
    LayerHeader lh = l.header;
    lh.format_major = major;
    const std::vector<uint8_t> layer =
        write_layer(lh, l.payload, l.carving, l.values, l.candidates, l.regions, l.faces, l.cell_values,
                    l.order, l.exact, l.edge_nodes, drop ? std::span<const uint8_t>{} : l.edge_values);
    out.insert(out.end(), layer.begin(), layer.end());
  }
  return out;
}

TEST(EdgeNodes, AnEighteenStreamGivesTheNodesTheirCornersMean) {
  const TorusWithFields torus(0);
  const auto& [m, given, f, in] = torus;
  // (As 20.0 writes it: re-written as 20.0 below.)
  EncodeOptions v20 = fields_options();
  v20.exact_ranks = ApexRanks::kAfterFlips;
  const auto encoded = encode(in, v20);
  ASSERT_TRUE(encoded.ok());
  // The same mesh as 18.0 wrote it: its offsets alone, no edge value section.
  EncodeOptions v18 = fields_options();
  v18.edge_nodes_v18 = true;
  const auto old = encode(in, v18);
  ASSERT_TRUE(old.ok());
  EXPECT_EQ(old->report.edge_value_bytes, 0u);
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(old->bytes, d).ok());
  EXPECT_EQ(d.header().version_major, kVersionMajorEdgeNodes);
  const OutputMesh out = decoded_mesh(d, "torus", true);
  ASSERT_GT(out.edge_nodes, 0u);
  const size_t base = out.points.size() - out.edge_nodes;
  size_t checked = 0;
  for (size_t c = 0; c < out.cells.size() && checked < 200; ++c)
    for (size_t e = 0; e < 6; ++e) {
      const uint32_t node = out.cell_edge_nodes[c][e];
      if (node == kNoEdgePoint || node < base) continue;
      const uint32_t a = out.cells[c][kCellEdges[e][0]], b = out.cells[c][kCellEdges[e][1]];
      const auto value = [&](uint32_t v) { return value_of(out.fields[0].bits[v], ValueType::kF64); };
      EXPECT_EQ(value(node), (value(a) + value(b)) / 2);
      ++checked;
    }
  EXPECT_GE(checked, 200u);
  // A 19.0 stream without it is refused.
  ProgressiveDecoder refused;
  const Status status =
      decode_stream(restreamed(encoded->bytes, kVersionMajorCreaseEdgeNodes, true), refused);
  EXPECT_NE(status.message().find("level 0's layer without its edge value section"), std::string::npos)
      << status.message();
  // The stream re-written as it is decodes as it did.
  EXPECT_EQ(restreamed(encoded->bytes, kVersionMajorCreaseEdgeNodes, false), encoded->bytes);
}

// A layer's edge value section where the flags have none, or in a layer
// but level 0's, is refused before its bytes are read.
TEST(EdgeNodes, AnEdgeValueSectionOnlyWithEdgeNodesAndValuesAtLevel0) {
  StreamHeader h;
  h.version_major = kVersionMajorPredictedEdgeNodes;
  h.grid.qbits = 14;
  h.level_count = 2;
  h.vertex_count = 8;
  const std::vector<uint8_t> payload(64, 0), one(1, 0), four(4, 0);
  const auto refusal = [&](uint16_t flags, uint16_t level, std::span<const uint8_t> values) {
    h.flags = flags;
    LayerHeader lh;
    lh.format_major = kVersionMajorPredictedEdgeNodes;
    lh.level = level;
    lh.new_vertices = 4;
    lh.level_vertices = level == 1 ? 4 : 8;
    lh.alpha = 1;
    const bool exact = flags & kFlagExact, level0 = level == 0;
    const std::vector<uint8_t> layer = write_layer(
        lh, payload, one, (flags & kFlagValues) ? std::span<const uint8_t>(four) : std::span<const uint8_t>{},
        {}, {}, {}, {}, {}, exact && level0 ? std::span<const uint8_t>(one) : std::span<const uint8_t>{},
        (flags & kFlagEdgeNodes) && level0 ? std::span<const uint8_t>(one) : std::span<const uint8_t>{},
        values);
    LayerWalk walk(h, UINT64_MAX, 0);
    if (level == 0) {  // (the walk starts at the coarsest level)
      LayerHeader base = lh;
      base.level = 1, base.new_vertices = base.level_vertices = 4;
      const std::vector<uint8_t> first =
          write_layer(base, payload, one,
                      (flags & kFlagValues) ? std::span<const uint8_t>(four) : std::span<const uint8_t>{});
      Layer l;
      EXPECT_TRUE(walk.next(first, l).ok());
    }
    Layer l;
    return walk.next(layer, l).message();
  };
  const uint16_t all = kFlagCarvingCorrections | kFlagExact | kFlagEdgeNodes | kFlagValues;
  EXPECT_NE(refusal(all & ~kFlagValues, 0, four)
                .find("an edge value section present without edge nodes and values"),
            std::string::npos);
  EXPECT_NE(refusal(all, 1, four).find("an edge value section in a layer but level 0's"), std::string::npos);
  EXPECT_NE(refusal(all, 0, {}).find("level 0's layer without its edge value section"), std::string::npos);
  EXPECT_EQ(refusal(all, 0, four), "");
}

// The nodes' values count against the decoder's limit with the vertices'.
TEST(EdgeNodes, TheNodesValuesCountAgainstTheLimit) {
  const TorusWithFields torus(0);
  const auto& [m, given, f, in] = torus;
  const auto encoded = encode(in, fields_options());
  ASSERT_TRUE(encoded.ok());
  // (5 components: the vertices' 1,440 values fit, with the nodes' not.)
  DecoderOptions options;
  options.max_values = 5 * m.points.size() + 10;
  ProgressiveDecoder d(options);
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  const ProgressiveDecoder::LevelCells level = d.level_cells();
  EXPECT_TRUE(d.edge_nodes(level).values.empty());
  EXPECT_EQ(d.mesh_status().code(), StatusCode::kLimitExceeded) << d.mesh_status().message();
}

// The edge value section alone: every truncation is refused, and a flipped
// bit is refused or decodes (never read past).
TEST(EdgeNodes, DamagedValueSectionsAreRefused) {
  const TorusWithFields torus(0);
  const auto& [m, given, f, in] = torus;
  const auto encoded = encode(in, fields_options());
  ASSERT_TRUE(encoded.ok());
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
  const ProgressiveDecoder::LevelCells level = d.level_cells();
  const ProgressiveDecoder::EdgeNodes nodes = d.edge_nodes(level);
  ASSERT_TRUE(d.mesh_status().ok());
  std::vector<FieldDescription> descriptions;
  for (const FieldValues& v : d.fields()) descriptions.push_back(v.description);
  // The section is the stream's last bytes.
  const std::vector<uint8_t> section(
      encoded->bytes.end() - static_cast<std::ptrdiff_t>(encoded->report.edge_value_bytes),
      encoded->bytes.end());
  std::vector<FieldValues> values;
  ASSERT_TRUE(
      decode_edge_node_values(section, descriptions, d.fields(), nodes.edges, nodes.present, values).ok());
  for (size_t k = 0; k < values.size(); ++k) EXPECT_EQ(values[k].bits, nodes.values[k].bits);
  // (Some 100 cuts and 400 flips, each decode costing a few milliseconds.)
  const size_t step = std::max<size_t>(1, section.size() / 100);
  for (size_t n = 0; n < section.size(); n += n < 16 ? 1 : step)
    EXPECT_FALSE(decode_edge_node_values(std::span(section).first(n), descriptions, d.fields(), nodes.edges,
                                         nodes.present, values)
                     .ok())
        << n;
  size_t refused = 0, flipped = 0;
  for (size_t i = 0; i < section.size(); i += i < 16 ? 1 : step * 2)
    for (int b = 0; b < 8; ++b) {
      std::vector<uint8_t> damaged = section;
      damaged[i] ^= static_cast<uint8_t>(1 << b);
      ++flipped;
      refused +=
          !decode_edge_node_values(damaged, descriptions, d.fields(), nodes.edges, nodes.present, values)
               .ok();
    }
  EXPECT_GT(refused, flipped / 4);
}

}  // namespace
}  // namespace dtm
