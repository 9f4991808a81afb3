// The reference shape every codec level is held to (spec/HIERARCHY.md §6):
// the boundary of the reference solid (the input's tetrahedra, or level 0's
// alpha carving). A level's boundary surface is measured against it both
// ways: from the reference's boundary vertices to the level's surface, and
// from the level's surface (its vertices and its triangles' centroids) to the
// reference's. The hierarchy builder checks every level with this one
// measurement and repairs where it exceeds D_max; the report shows its
// figures. Distances are inexact (CGAL's projections, doubles): a measurement.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "common/grid.h"
#include "core/quantize.h"
#include "core/surface_distance.h"
#include "core/triangle_distance_tree.h"

namespace dtm {

// The input's tetrahedra on the grid (indices of q.points), without those
// quantization collapsed (two corners on one grid point), ordered by their
// smallest vertex (ties by their corners): the grid points are in
// lexicographic order, so this order sweeps space and whatever is built from
// the tetrahedra reads their corners in order.
std::vector<std::array<uint32_t, 4>> grid_tetrahedra(std::span<const std::array<uint32_t, 4>> tets,
                                                     const QuantizedPoints& q);
// The same, made of the input's tetrahedra where they lie: no copy of them
// (a gigabyte at 60M tetrahedra).
// `labels`, when given, holds a value per tetrahedron (its region) and
// follows it.
void grid_tetrahedra_in_place(std::vector<std::array<uint32_t, 4>>& tets, const QuantizedPoints& q,
                              std::vector<int32_t>* labels = nullptr);

// One level's surface measured against the reference. The per-point
// figures are squared distances in grid units.
struct ShapeMeasurement {
  DistanceSummary to_level;      // the reference's boundary vertices to the level's surface
  DistanceSummary to_reference;  // the level's surface to the reference's
  DistanceSummary both;          // the larger max; the mean over every point measured
  // Per reference boundary vertex (ReferenceShape::boundary_points()): its
  // squared distance to the level's surface (the triangle nearest it:
  // ReferenceShape::nearest_triangle(), not copied here).
  std::vector<double> reference_squared;
  // The level's surface vertices (indices into the measured points) and
  // each one's squared distance; each triangle's centroid's.
  std::vector<uint32_t> surface_vertices;
  std::vector<double> vertex_squared;
  std::vector<double> centroid_squared;
};

// What a reference shape measures against and never changes: its boundary
// triangles, their keys, its boundary vertices and the search structure of
// its surface. Shared (read only, by any thread) by the shapes of blocks
// whose regions meet the whole boundary (codec/blocks/rank_reference.h):
// building it once is most of what such a block's shape costs, and every
// rank that builds such a block holds it (its search structure is
// core/triangle_distance_tree.h's for that: about 30 bytes a triangle).
struct ReferenceBoundary {
  // `keep_triangles` false: `triangles` is left empty once the rest is made
  // (a block's shape measures with the keys and the tree alone; bunny_10m's
  // whole boundary held 17 MiB less on the rank that holds it).
  ReferenceBoundary(std::span<const GridPoint> points, std::vector<std::array<uint32_t, 3>> boundary,
                    bool keep_triangles = true);

  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<std::array<uint32_t, 3>> keys;  // each triangle's ids sorted, the list sorted
  std::vector<uint32_t> ids;                  // grid ids of points(), ascending
  TriangleDistanceTree surface;
  // The boundary's vertices, as `ids` names them: the tree's corners (the
  // same points in the same order), not held twice.
  std::span<const GridPoint> points() const { return surface.corners(); }
};

class ReferenceShape {
 public:
  // `tets` index `points` (the grid points); their orientation does not matter.
  ReferenceShape(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> tets);
  // Of a solid of several regions (`region` per tetrahedron, region_solid.h):
  // its interfaces are measured as its outer boundary is.
  ReferenceShape(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> tets,
                 std::span<const uint8_t> region);
  // The same from the reference's boundary triangles (indices into
  // `points`): a part of a larger reference, for one block of a level
  // built block by block (which keeps no boundary_triangles()).
  static ReferenceShape from_boundary(std::span<const GridPoint> points,
                                      std::vector<std::array<uint32_t, 3>> boundary);
  // The same on a boundary built before: what it measures is the shape's
  // own, as though made from the boundary's triangles.
  explicit ReferenceShape(std::shared_ptr<const ReferenceBoundary> boundary);

  size_t boundary_vertices() const { return boundary_->points().size(); }
  std::span<const GridPoint> boundary_points() const { return boundary_->points(); }
  // The grid ids of boundary_points(), ascending.
  std::span<const uint32_t> boundary_ids() const { return boundary_->ids; }
  // Empty for a shape from_boundary() or on a ReferenceBoundary that keeps none.
  std::span<const std::array<uint32_t, 3>> boundary_triangles() const { return boundary_->triangles; }

  // Measures the surface `triangles` (indices into `points`), whose points
  // are named across calls by `ids` (grid-point indices): meant to be
  // called level after level, and repair after repair, of one hierarchy,
  // what a surface shares with the one measured before it is not measured
  // again. No triangle: every distance to the level is +infinity.
  ShapeMeasurement measure(std::span<const GridPoint> points, std::span<const uint32_t> ids,
                           std::span<const std::array<uint32_t, 3>> triangles);
  // The surface triangle the last measure() found nearest reference
  // boundary vertex i (its ids, sorted).
  std::array<uint32_t, 3> nearest_triangle(size_t i) const { return to_level_.nearest_triangle(i); }

  // The same for a level given by its carved cells (indices into the grid
  // points the reference was made with), figures only.
  ShapeMeasurement distance(std::span<const std::array<uint32_t, 4>> cells,
                            std::span<const GridPoint> points);

 private:
  ReferenceShape(std::span<const GridPoint> points, std::vector<std::array<uint32_t, 3>> boundary,
                 bool keep_triangles);

  std::shared_ptr<const ReferenceBoundary> boundary_;
  SurfaceDistanceTracker to_level_;  // from the boundary's points
  // Squared distance of a grid point to the reference surface, once
  // measured (a level's surface vertices are mostly the previous level's);
  // 0 for the reference's own boundary vertices, not held here.
  std::unordered_map<uint32_t, double> to_reference_;
  std::optional<double> known_squared(uint32_t id) const;
  // The last measured surface's triangles off the reference (ids sorted)
  // and their centroids' squared distances to it, sorted by the ids.
  std::vector<std::pair<std::array<uint32_t, 3>, double>> centroid_squared_;
};

}  // namespace dtm
