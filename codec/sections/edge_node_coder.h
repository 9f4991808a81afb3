// The nodes on level 0's edges (format 18.0, kFlagEdgeNodes, spec/FORMAT.md
// §3.11; meshenc --exact of a second-order mesh), encoder and decoder side
// by side.
//
// A second-order mesh (gmsh -order 2, Netgen's SecondOrder(), TetGen -o2:
// 10-node tetrahedra, the default elements of most structural analysis)
// has a node on every edge of its cells: at the edge's midpoint inside the
// solid, moved onto the geometry on a curved boundary. An exact stream's
// level 0 is the input's cells, so its edges are the input's: this section
// gives each edge's node as its offset from the midpoint of the edge's
// decoded corners, in half grid steps. Most nodes are midpoints (offset 0,
// one bit that costs next to nothing away from the surface); a curved
// boundary's are coded component by component, from 19.0 as their
// difference from where the surface's normals put them
// (edge_node_prediction.cpp).
//
// The edges are walked in one order both sides compute from level 0's kept
// cells (level_edges()): the cells in the canonical order, each one's six
// edges (kCellEdges of its corners in ascending order), each edge the
// first time it is met.
//
// With per-vertex fields, the edge value section (format 19.0, §3.12)
// follows: each node's values, predicted from its edge's corners'.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/value_coder.h"
#include "codec/sections/value_fields.h"
#include "common/status.h"
#include "mesh/delaunay.h"
#include "mesh/geometry.h"

namespace dtm {

// A cell's edges as pairs of its corners, in the order a second-order
// tetrahedron's file lists their nodes once mapped (tools/formats/
// second_order.h's kTetEdges).
inline constexpr std::array<std::array<uint8_t, 2>, 6> kCellEdges = {
    {{{0, 1}}, {{0, 2}}, {{0, 3}}, {{1, 2}}, {{1, 3}}, {{2, 3}}}};

// An edge's key whichever way round its corners are given: the lower in
// the high 32 bits.
inline uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? uint64_t{a} << 32 | b : uint64_t{b} << 32 | a;
}

// The edges of a level's kept cells: each edge's corners (the lower first),
// whether it is an edge of the level's surface, and per kept cell, in the
// canonical order, its six edges (kCellEdges of its corners in ascending
// order, however the cell lists them) as indices into `corners`.
struct LevelEdges {
  std::vector<std::array<uint32_t, 2>> corners;
  std::vector<uint8_t> on_surface;
  std::vector<std::array<uint32_t, 6>> cell_edges;
};
// `kept`: per cell of `mesh` whether the level keeps it (its region, or 0);
// `order`: the canonical order of mesh's cells.
LevelEdges level_edges(const TetMesh& mesh, std::span<const uint8_t> kept, std::span<const uint32_t> order);

// Per edge of a LevelEdges, its node: none, or twice its position in grid
// units less the sum of the edge's corners (0 for the midpoint).
struct EdgeNodeOffsets {
  std::vector<uint8_t> present;
  std::vector<std::array<int64_t, 3>> offset;
};

// An offset's components lie strictly within +-edge_node_reach(qbits), in
// half grid steps: a node less than twice the grid's extent from its edge's
// midpoint on each axis.
inline int64_t edge_node_reach(int qbits) { return int64_t{1} << (qbits + 2); }

// Format 19.0: where a curved surface's nodes are expected: off a surface
// edge's midpoint as a curved (PN) triangle's edge passes, from its corners'
// normals (the sum of their surface faces' normals), in half grid steps,
// within +-2^(qbits + 1). Format 20.0 (`creases`): the surface's creases
// apart (its edges where it turns by more than 60 degrees, or where other
// than two of its faces meet): each corner's normal is its faces' on the
// edge's side of them, and a crease edge's node is expected where a curve
// through its neighbours along the crease passes (a cubic with their
// chords' directions as its tangents). Exact integer arithmetic
// (spec/FORMAT.md §3.11): both sides predict alike. `mesh`, `kept`: the
// level's cells, as level_edges() took them; `points`: the level's
// (viewed, not copied).
class EdgeNodePredictor {
 public:
  EdgeNodePredictor(const TetMesh& mesh, std::span<const uint8_t> kept, std::span<const GridPoint> points,
                    int qbits, bool creases);
  // The predicted offset of the node on the surface edge from a to b.
  std::array<int64_t, 3> offset(uint32_t a, uint32_t b) const;

 private:
  using Vec = std::array<int64_t, 3>;
  static constexpr uint32_t kOffSurface = UINT32_MAX;  // slot_: a point not on the surface
  // neighbour_sector_: a crease edge; offset(): an edge not on the surface.
  static constexpr uint32_t kCrease = UINT32_MAX, kNotSurfaceEdge = UINT32_MAX - 1;
  // Where the node of the edge a-b lies off its midpoint, in half steps, as
  // the corners' normals na and nb put it (zero normals: no bulge there).
  std::array<Int128, 3> normals_offset(uint32_t a, uint32_t b, const Vec& na, const Vec& nb) const;
  // 20.0: a crease edge's, from the crease's curve through its corners.
  std::array<Int128, 3> crease_offset(uint32_t a, uint32_t b) const;

  std::span<const GridPoint> points_;
  int qbits_ = 0;
  bool creases_ = false;
  std::vector<uint32_t> slot_;  // per point, its index among the surface's vertices, or kOffSurface
  std::vector<Vec> normals_;    // 19.0: per surface vertex; 20.0: per sector about one (below)
  // 20.0: per surface vertex (slot), its neighbours on the surface,
  // ascending (neighbour_start_: where they start in neighbour_vertex_),
  // each with its edge's sector at the vertex (an index into normals_: the
  // faces about the vertex that meet across edges that are not creases),
  // or kCrease; and its crease edges: how many, and the
  // first two's other ends.
  std::vector<uint32_t> neighbour_start_, neighbour_vertex_, neighbour_sector_;
  std::vector<std::array<uint32_t, 3>> crease_ends_;
};

// `predictor`: 19.0's or 20.0's, each moved node coded as its offset's
// difference from the predicted one on a surface edge; null: 18.0's
// section, the offsets themselves. `nodes`' offsets lie within edge_node_reach().
std::vector<uint8_t> encode_edge_nodes(const LevelEdges& edges, const EdgeNodeOffsets& nodes, int qbits,
                                       const EdgeNodePredictor* predictor = nullptr);
// kCorrupt unless the section gives every edge's node within reach, a
// moved node with a nonzero offset, and ends where its bytes do.
Status decode_edge_nodes(std::span<const uint8_t> section, const LevelEdges& edges, int qbits,
                         EdgeNodeOffsets& nodes, const EdgeNodePredictor* predictor = nullptr);

// The edge value section (19.0, §3.12) is a bricked chunk's value section
// (FieldSectionEncoder::encode_chunk, decode_chunk_values) whose known
// points are the level's vertices and whose points are the present nodes in
// the walk's order, each predicted from its edge's two corners alone (the
// rounded mean of their values, where the field is smooth within
// O(length^2) of the node's): these are their neighbours.
std::vector<Neighbours> edge_node_neighbours(const LevelEdges& edges, std::span<const uint8_t> present);

// Read: the present nodes' values, one FieldValues per field of `fields`,
// node-major in the walk's order, given the level's vertices' decoded values
// (`vertex_values`, one per field). kCorrupt if the section is damaged.
Status decode_edge_node_values(std::span<const uint8_t> section, std::span<const FieldDescription> fields,
                               std::span<const FieldValues> vertex_values, const LevelEdges& edges,
                               std::span<const uint8_t> present, std::vector<FieldValues>& out);

}  // namespace dtm
