// The level-of-detail hierarchy of the seed paper (§II): level 0 holds every
// grid point; each coarser level removes one set of vertices that is
// independent in the finer level's Delaunay tetrahedralization: boundary
// vertices whose removal keeps the surface within Dmax (§II.2), then interior
// vertices by ascending importance (§II.3-II.4). Each level's mesh is the
// alpha-carved Delaunay tetrahedralization of its vertices, so only vertex
// sets need to be stored.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/progress.h"
#include "common/status.h"
#include "core/level.h"
#include "core/solid.h"
#include "core/solid_difference.h"
#include "core/surface_distance.h"

namespace dtm {

struct HierarchyOptions {
  AlphaPolicy alpha;
  // The carving (spec/HIERARCHY.md §3). false: the paper's, alpha decides.
  // true: every level keeps the cells whose centroid is in the reference
  // solid; alpha is only the decoder's prediction, which the stream corrects.
  bool carve_to_reference = false;
  // The reference solid's tetrahedra (grid-point indices), with
  // carve_to_reference. Without them, `reference_solid` if given (a scan's
  // voxels, core/voxel_solid.h; level 0's carving is then the shape the
  // levels are measured against), else level 0's alpha carving.
  std::span<const std::array<uint32_t, 4>> reference_cells;
  // Per reference cell, its region (1 + the index of its label in the
  // stream's region table, core/region_solid.h); empty: one region. Every
  // level's kept cells then carry their region in Level::kept.
  std::span<const uint8_t> reference_regions;
  const Solid* reference_solid = nullptr;
  // How much a level removes: independent-set passes, each in the then
  // current tetrahedralization, until this share of the finer level's
  // vertices is gone (or nothing more passes the guards). 0: one pass (the
  // paper). A level that reaches less than 40% of this share is not built:
  // the finer level is the coarsest.
  double removal_share = 0;
  double dmax = 1.0;              // boundary tolerance, grid units
  int max_levels = 0;             // coarser levels to build at most; 0 = no limit
  size_t min_base_vertices = 16;  // never build a level with fewer vertices
  // The paper's rule: the first level that removes no boundary vertex is the
  // last one built.
  bool stop_when_boundary_is_final = true;
  // Quality guard (0 = off): a removal is accepted only if the cells that
  // refill its cavity have a smallest solid angle >= min(quality_guard, the
  // smallest solid angle of the star they replace). With 0.5513 (the regular
  // tetrahedron's) it means "never worse than before".
  double quality_guard = 0;
  // Relative quality guard (0 = off): a removal is accepted only if the
  // refill's smallest solid angle is >= quality_ratio x the star's.
  double quality_ratio = 0;
  // Average quality floor (0 = off): a removal is accepted only while the
  // level's average smallest solid angle, as the removals accepted so far
  // leave it, stays >= average_quality_floor x level 0's. Removals that do
  // not lower it come first, in the usual order; the others are then taken
  // least damaging first while the margin lasts. Exact with a reference
  // solid (the refill's kept cells are the next level's); with alpha
  // carving, the next level's alpha may keep other cells.
  double average_quality_floor = 0;
  // The floor never above this absolute average smallest solid angle (0 =
  // no cap): what Delaunay levels of well-spaced points reach, so that a
  // mesher's best-shaped output (Netgen's 0.35) gets coarser levels too.
  double quality_floor_cap = 0;
  // The boundary error statistics (an AABB-tree query per original boundary
  // vertex and level) are a measurement, not part of the construction: the
  // benchmark reports the build with and without them.
  bool measure_boundary_error = true;
  // Told each phase as it starts (common/progress.h).
  PhaseCallback on_phase;
};

// The distance between a reference's boundary and a level's, each way: from
// the reference's boundary vertices to the level's surface, from the level's
// surface (its vertices and triangle centroids) to the reference's, and both
// together (the larger max, the mean over every point measured).
struct ShapeFigures {
  DistanceSummary to_level, to_reference, both;
  uint64_t reference_vertices = 0;  // the reference's boundary vertices, each measured to the level
};

struct LevelStats {
  int level = 0;
  uint64_t vertices = 0;
  uint64_t boundary_vertices = 0;
  uint64_t removed_interior = 0;  // removed from the finer level to make this one
  uint64_t removed_boundary = 0;
  uint64_t rejected_by_quality = 0;  // candidates the quality rules kept (paper preset)
  int passes = 0;                    // independent sets removed to make this level (paper preset)
  // The codec preset (spec/HIERARCHY.md §6.1-6.2): vertices the whole-level
  // choice kept, those the repair put back, and its rounds.
  uint64_t chosen = 0;
  uint64_t put_back = 0;
  int repair_rounds = 0;
  // With a reference solid (the codec preset): the distance between its
  // boundary and this level's (grid units), as the builder checked it.
  std::optional<ShapeFigures> reference_shape;
  double alpha = 0;                // grid units
  uint64_t tetrahedra = 0;         // cells of M_l
  double avg_min_solid_angle = 0;  // over M_l cells, steradians
  double min_solid_angle = 0;
  double max_boundary_error = 0;  // grid units: level-0 boundary vertices to this boundary
  double mean_boundary_error = 0;
};

struct Level {
  std::vector<uint32_t> vertices;  // indices into the grid points, ascending
  double alpha = 0;                // grid units
  // M_l, vertices named by grid-point index, when alpha carves (the paper
  // preset); empty with carve_to_reference, where delaunay and kept hold it.
  // carved_cells() gives it either way. Cell order is not canonical.
  std::vector<std::array<uint32_t, 4>> mesh;
  // With carve_to_reference: DT(V_l) whole (grid-point indices) and, per
  // cell, whether M_l keeps it; what the stream's corrections are made from.
  TetMesh delaunay;
  std::vector<uint8_t> kept;
  LevelStats stats;

  // M_l's cells (grid-point indices).
  std::vector<std::array<uint32_t, 4>> carved_cells() const;
};

struct Hierarchy {
  std::vector<Level> levels;  // levels[0] is the finest
  // With a reference solid (the codec preset): how many vertices its
  // boundary has, and level 0's solid against it (core/solid_difference.h).
  uint64_t reference_boundary_vertices = 0;
  std::optional<SolidDifference> level0_difference;
};

// Called once per level as soon as it is complete.
using LevelCallback = std::function<void(const Level&)>;

// Builds the hierarchy over `points` (distinct grid points). kInvalidInput
// if level 0 does not span three dimensions.
StatusOr<Hierarchy> build_hierarchy(std::span<const GridPoint> points, const HierarchyOptions& options,
                                    const LevelCallback& on_level = {});

// The cells of a level in canonical form: each cell's vertices sorted,
// cells sorted. Two meshes are the same iff their canonical forms are equal.
std::vector<std::array<uint32_t, 4>> canonical_cells(std::vector<std::array<uint32_t, 4>> cells);

}  // namespace dtm
