// One level of detail analysed as the seed paper does (§II.1): the Delaunay
// tetrahedralization of the level's points, alpha (eq. 2.1), the carved mesh,
// solid angles (eq. 2.2-2.3), the boundary, and the volumes behind the
// importance value (eq. 2.4).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/grid.h"
#include "common/status.h"
#include "mesh/carving.h"
#include "mesh/delaunay.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"

namespace dtm {

// How alpha_l is chosen; the carved mesh M_l keeps the cells of
// circumradius <= alpha_l (mesh/carving.h).
struct AlphaPolicy {
  using Kind = AlphaKind;
  Kind kind = Kind::kPaper;
  double fixed_value = 0;  // grid units, for kFixed
  // A level carved to a reference keeps no cell whose circumradius exceeds
  // this (grid units; 0: no bound). Bricked streams (spec/FORMAT.md §3.5)
  // need the bound: a region reader decodes the points within twice the
  // largest kept circumradius of the region. The cells above it are mostly
  // nearly flat (slivers on the solid's flat faces): dropping them moves the
  // boundary by their thickness. The very number the layer header holds,
  // compared as the decoder compares it (not a multiple of alpha, whose
  // product may round a unit in the last place away).
  double kept_radius = 0;
};

// A vertex is interior when the solid angles of its mesh cells add up to 4*pi
// within this tolerance (steradians). Computed on exact grid input the sum of
// an interior vertex is off by ~1e-13; the smallest exterior angle a
// boundary vertex leaves open is many orders of magnitude above that.
inline constexpr double kSolidAngleTolerance = 1e-7;

struct LevelGeometry {
  std::vector<GridPoint> points;  // vertex v is points[v]
  TetMesh dt;                     // DT(V_l)
  Csr neighbors;                  // edge graph of DT(V_l)
  Csr cells_of_vertex;            // cells of DT(V_l) around each vertex
  uint64_t finite_edges = 0;
  double mean_edge_length = 0;  // grid units
  double alpha = 0;             // grid units

  std::vector<uint8_t> in_mesh;              // per cell: belongs to M_l
  std::vector<double> cell_min_solid_angle;  // per M_l cell: the smallest of its 4 solid angles
  std::vector<double> solid_angle_sum;       // per vertex, over its M_l cells
  // Per vertex: 6 x the volume of its M_l cells, exact, so that importance
  // values (and their ties) do not depend on the order cells are listed in.
  std::vector<Int128> mesh_volume6;
  std::vector<uint8_t> boundary;  // per vertex: solid-angle boundary (§II.1.b)
  uint64_t mesh_cells = 0;

  size_t size() const { return points.size(); }
};

// Analyses the level whose vertices are `points` (distinct grid points).
// kInvalidInput if they do not span 3D. M_l is carved by alpha.
StatusOr<LevelGeometry> analyze_level(std::vector<GridPoint> points, const AlphaPolicy& policy);

// The same, given the Delaunay tetrahedralization of `points` already, and,
// optionally, the verdict on each of its cells (M_l keeps cell c when
// verdicts[c] != 0: the reference solid's carving, or a decoder's);
// alpha is computed all the same: it is the decoder's prediction.
StatusOr<LevelGeometry> analyze_level(std::vector<GridPoint> points, TetMesh dt, const AlphaPolicy& policy,
                                      std::span<const uint8_t> verdicts = {});

// The boundary surface of M_l: its triangles (local vertices, outward) and,
// per vertex, the triangles around it. The boundary simplification and the
// shape guard both work on it.
// A level's surface as its coarsening sees it: its boundary triangles and,
// with regions (in_mesh holding 1 + the region), the interfaces between
// them (each once, oriented from the lower region), so that an interface's
// vertices are kept or removed by the chord test as the boundary's are.
struct LevelSurface {
  std::vector<std::array<uint32_t, 3>> triangles;
  Csr around;
  std::vector<uint8_t> interface;  // per vertex: on an interface (empty: no region has one)
  // A vertex the coarsening treats as on the surface: on the boundary or an
  // interface, with surface triangles around it.
  bool holds(const std::vector<uint8_t>& boundary, uint32_t v) const {
    return (boundary[v] || (!interface.empty() && interface[v])) && !around.row(v).empty();
  }
};
LevelSurface level_surface(const LevelGeometry& level);

// The paper's quality figures of M_l (§III, Tables 1-2): mean and minimum
// over its cells of each cell's smallest solid angle, and its boundary size.
struct MeshQuality {
  double avg_min_solid_angle = 0;
  double min_solid_angle = 0;
  uint64_t boundary_vertices = 0;
};
MeshQuality mesh_quality(const LevelGeometry& level);

// The topological boundary of M_l: vertices of its boundary faces, plus
// vertices in no M_l cell. The solid-angle test must agree with it.
std::vector<uint8_t> topological_boundary(const LevelGeometry& level);

// The cells of M_l (in_mesh), their vertices named by `vertices` (the level's
// local index -> grid-point index), in the triangulation's order.
std::vector<std::array<uint32_t, 4>> carved_cells(const LevelGeometry& L, std::span<const uint32_t> vertices);

}  // namespace dtm
