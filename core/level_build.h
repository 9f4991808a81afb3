// One coarser codec level (spec/HIERARCHY.md §6.2): the chosen subset of the
// finer level tetrahedralized in one batch, carved to the reference solid,
// checked in one sweep against every bound, and repaired where one breaks by
// putting back removed vertices there (local insertions, a few rounds). It
// ends: every round puts back at least one vertex or stops, and putting back
// everything would give the finer level, which meets the bounds.
//
// The bounds, checked with the same measurement the report shows:
// * shape: the reference's boundary vertices within D_max of the level's
//   surface, and the level's surface (its vertices and its triangles'
//   centroids) within D_max of the reference's; a place where the finer
//   level was already farther (a surface triangle or vertex it had, a
//   reference vertex it left as far) is inherited, not broken here;
// * quality: the average smallest solid angle of the carved cells at least
//   the floor.
// Where a bound breaks, the removed vertices that would change it are put
// back: those inside the circumspheres of the cells on both sides of a far
// surface triangle (the vertices those cells are in conflict with: each one
// put back destroys the cell), the nearest few within the distance of a far
// reference vertex, and those in conflict with the worst-shaped cells until
// the quality's deficit is covered; a place still broken gets one more
// vertex back per cell each round.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"
#include "core/level.h"
#include "core/reference_shape.h"
#include "core/solid.h"

namespace dtm {

struct LevelBounds {
  double dmax = 1.0;         // grid units
  double quality_floor = 0;  // the smallest average smallest solid angle (sr); 0 = none
  int repair_rounds = 12;
  // A block of a level built block by block (codec/blocks/block_levels.h): only the
  // places this box owns are checked (a surface triangle or a cell by its
  // lexicographically smallest corner, a reference vertex by itself), and
  // the quality is the average over the cells it owns; what the repair puts
  // back may lie anywhere in the points given. nullptr: the whole level.
  const GridBox* owned = nullptr;
  // The level keeps no cell of circumradius (carving_radius) above this: a
  // bricked stream's kept_radius (spec/FORMAT.md §3.5). 0: no bound.
  double kept_radius = 0;
  // false: the built level is not analysed (BuiltLevel::surface and all of
  // ::geometry but its dt stay empty), its vertex set, checks,
  // tetrahedralization and solid_regions are all the caller needs.
  bool analyze = true;
};

// The reference a codec level is carved to and measured against.
struct LevelReference {
  const Solid* solid = nullptr;
  ReferenceShape* shape = nullptr;
};

// A level's surface as the next level's check needs it: what it may inherit.
struct SurfaceRecord {
  std::vector<std::array<uint32_t, 3>> triangles;  // grid ids, each sorted, the list sorted
  std::vector<uint32_t> vertices;                  // grid ids, sorted
  std::vector<double> reference_squared;           // per reference boundary point
};

// The outward boundary triangles of the carved level and, per triangle, the
// cell inside it and the cell outside it (-1: the convex hull).
struct CarvedSurface {
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<std::array<int32_t, 2>> cells;
};
CarvedSurface carved_surface(const TetMesh& dt, std::span<const uint8_t> kept,
                             std::span<const GridPoint> points);

// The record of a surface (vertices named by `ids`) and its measurement.
SurfaceRecord record_surface(std::span<const uint32_t> ids,
                             std::span<const std::array<uint32_t, 3>> triangles,
                             const ShapeMeasurement& measured);

struct BuiltLevel {
  LevelGeometry geometry;          // carved to the reference
  std::vector<uint32_t> vertices;  // grid ids, ascending
  ShapeMeasurement shape;          // of the level as built
  SurfaceRecord surface;
  double quality = 0;       // its average smallest solid angle
  uint64_t chosen = 0;      // vertices the choice kept
  uint64_t put_back = 0;    // vertices the repair put back
  int repair_rounds = 0;    // rounds that put some back
  uint64_t shape_left = 0;  // places still beyond D_max when the rounds ran out
  bool quality_met = true;
  // The last check's: the sum of the smallest solid angles of the kept
  // cells the quality is taken over and their count (quality is their
  // ratio), and the fins and slots left. A build whose last check found
  // nothing to repair (shape_left and fins_left 0, quality_met) is clean:
  // a block built block by block can then be checked again where a
  // neighbour changed it, rather than built again (codec/blocks/block_levels.h).
  double quality_sum = 0;
  uint64_t quality_cells = 0;
  uint64_t fins_left = 0;
  // Not analysed (LevelBounds::analyze false): per cell of geometry.dt,
  // the reference solid's region at its centroid (Solid::verdicts), kept
  // or not.
  std::vector<uint8_t> solid_regions;
};

// `fine_points`: the finer level's points (its vertices `fine_vertices`,
// grid ids); `keep`: the choice, per vertex of the finer level. `phase` is
// told what the build is doing as it goes.
StatusOr<BuiltLevel> build_coarser_level(std::span<const GridPoint> fine_points,
                                         std::span<const uint32_t> fine_vertices,
                                         const SurfaceRecord& fine_surface, std::span<const uint8_t> keep,
                                         const LevelReference& reference, const LevelBounds& bounds,
                                         const AlphaPolicy& alpha,
                                         const std::function<void(const char*)>& phase);

}  // namespace dtm
