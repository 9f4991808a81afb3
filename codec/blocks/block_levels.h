// The codec preset's levels built block by block (spec/HIERARCHY.md §6.5),
// for bricked streams: the work of one level is split into boxes of the
// grid (blocks, codec/blocks/block_runs.h), and each block's part is a function of the level's
// points and the reference inside the block grown by a halo, nothing else.
// So the levels and the stream are the same whichever process builds which
// block, in whatever order: one process, or any number of MPI ranks
// (codec/blocks/bricked_encoder.h runs the blocks and merges their results).
//
// A block's work at level l, in two steps:
// * analyse(): the Delaunay tetrahedralization of V_l in the block's
//   region, carved to the reference (cells above kept_radius dropped), and
//   from it what the block owns: its figures, its part of the level's
//   surface record, its bricks' carving sections (spec/FORMAT.md §3.5) and
//   the coarser level's choice for its vertices (core/coarsening.h);
// * build(): the chosen vertices in the region tetrahedralized, checked
//   and repaired (core/level_build.h) at the places the block owns; what it
//   puts back may lie anywhere in the region.
// A block owns the vertices in its box, a cell or surface triangle by its
// lexicographically smallest corner, a brick's cells as §3.5 says. The halo
// is 2 kept_radius + D_max (and 2 grid units), kept_radius the level's
// for analyse() and the coarser level's for build(): every cell a block
// owns whose circumradius is at most kept_radius has its circumsphere
// inside the region, so it is a cell of the whole level's
// tetrahedralization, and so are the neighbours its carving contexts read
// (owned by the same brick); so is a kept cell of a surface triangle
// within D_max of a reference vertex in the box; and a build's checks see
// no farther (bricked_encoder.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "codec/sections/value_fields.h"
#include "codec/stream/layer_coder.h"
#include "common/grid.h"
#include "common/status.h"
#include "core/cell_sources.h"
#include "core/coarsening.h"
#include "core/face_tags.h"
#include "core/level_build.h"
#include "core/reference_shape.h"
#include "core/solid.h"

namespace dtm {

// Every grid point by Morton code: the points of a level inside a box.
// Holds their ids only (4 bytes a point), the codes made again from the
// points when a search reads them.
class MortonIndex {
 public:
  MortonIndex(std::span<const GridPoint> points, int qbits);
  // The grid ids of the points inside `box` with level_of[id] >= level, ascending.
  std::vector<uint32_t> inside(const GridBox& box, std::span<const uint8_t> level_of, int level) const;
  // The Morton codes of the points with level_of >= level, ascending, and their ids.
  void level(std::span<const uint8_t> level_of, int level, std::vector<MortonCode>& codes,
             std::vector<uint32_t>* ids = nullptr) const;
  // Their ids alone (a code takes 16 bytes, an id 4).
  std::vector<uint32_t> level_ids(std::span<const uint8_t> level_of, int level) const;
  // The codes in [first, last) of the points with level_of >= level,
  // ascending, and their ids in that order (a brick's points, found by two
  // binary searches, not held for the whole level).
  void between(MortonCode first, MortonCode last, std::span<const uint8_t> level_of, int level,
               std::vector<MortonCode>& codes, std::vector<uint32_t>* ids = nullptr) const;
  int qbits() const { return qbits_; }

 private:
  MortonCode code_of(uint32_t id) const { return morton_encode(points_[id], qbits_); }
  // Where the first point of code `code` or above is in ids_ (two binary
  // searches make a stretch of the index).
  size_t first_at(MortonCode code) const;
  // How many points have level_of >= level (what level() and level_ids() make).
  size_t count_at(std::span<const uint8_t> level_of, int level) const;

  int qbits_;
  std::span<const GridPoint> points_;  // the caller's, which must outlive the index
  std::vector<uint32_t> ids_;          // the grid ids by Morton code, ascending
};

// The reference's boundary triangles by place: those whose bounding box
// meets a box.
class TriangleIndex {
 public:
  TriangleIndex(std::span<const GridPoint> points, std::vector<std::array<uint32_t, 3>> triangles, int qbits);
  std::vector<std::array<uint32_t, 3>> meeting(const GridBox& box) const;
  size_t size() const { return triangles_.size(); }

 private:
  // The Morton code of triangle k's box's low corner (made again from the
  // points when a search reads it, not held: 16 bytes a triangle, 22 MiB
  // for bunny_10m's boundary on every rank).
  MortonCode anchor_of(size_t k) const;
  // Where the first triangle of anchor `code` or above is.
  size_t first_at(MortonCode code) const;

  std::span<const GridPoint> points_;
  std::vector<std::array<uint32_t, 3>> triangles_;  // ascending by anchor_of()
  std::array<int64_t, 3> extent_{};                 // the largest box, per axis
  int qbits_;
};

// What a block is carved to and measured against: the reference solid
// (the whole reference's, shared by every block), and the reference's
// boundary triangles meeting the block's region, whose shape measure()
// remembers nothing of another block's.
struct BlockReference {
  const Solid* solid = nullptr;
  std::optional<ReferenceShape> shape;
};

// A block of level l: its box, its region, and V_l's points in the region.
struct BlockRegion {
  GridBox owned, region;
  std::vector<uint32_t> ids;  // grid ids, ascending
  std::vector<GridPoint> points;
};

// The figures of what a block owns, to be added up over the blocks in
// block order (the sums are then the same for any number of processes).
struct DistanceSums {
  double max = 0, sum = 0;
  uint64_t count = 0;
  void add(double squared);
  void add(const DistanceSums& o);
};
struct BlockFigures {
  uint64_t vertices = 0, boundary_vertices = 0, cells = 0;
  double quality_sum = 0, quality_min = INFINITY;
  DistanceSums to_level, to_reference;
  uint64_t cell_hash = 0;  // the wrapping sum of the owned cells' hashes (codec/stream/format.h)
  // The owned cells inside the reference solid, thicker than D_max, that
  // the kept radius drops: how many, and the largest circumradius among
  // them (0: none). A graded mesh's coarse inside holds cells far larger
  // than its mean spacing says; a flat cell on the solid's surface may have
  // any circumradius, and dropping it moves the surface by its thickness,
  // so thinner cells are not counted.
  uint64_t dropped_thick = 0;
  double dropped_thick_radius = 0;
  // With cell values: the owned kept cells that are input tetrahedra, and
  // those given the nearest of their vertices' (core/cell_sources.h).
  uint64_t cells_from_input = 0, cells_from_nearest = 0;
  // With tagged faces: the input's tagged triangles among the tagged
  // surface faces the block's bricks code.
  uint64_t tagged_faces_kept = 0;
};

struct BlockAnalysisOptions {
  int qbits = 0;
  double alpha = 0, kept_radius = 0;
  double dmax = 0;  // grid units: a dropped cell thicker than this counts as thick (BlockFigures)
  // Bricks of the layer whose carving sections the block codes (the
  // stream's brick depth for this level); -1: none.
  int brick_depth = -1;
  // The reference's regions (spec/FORMAT.md §3.5, 15.0): with 2 or more,
  // the bricks' region sections are coded too.
  size_t region_count = 0;
  // Choose the coarser level's vertices (else the level is the coarsest).
  std::optional<CoarseningOptions> choice;
  // Level 0 without reference tetrahedra: its owned cells (carved by
  // alpha, or by the voxels) are the reference of the coarser levels.
  bool collect_cells = false;
  // Level 0 with cell data (spec/FORMAT.md §3.5, 16.0): the bricks' cell
  // value sections are coded too, each kept cell taking the values of the
  // input tetrahedron `sources` finds for it (its points' indices).
  const CellSourceIndex* cell_sources = nullptr;
  const FieldSectionEncoder* cell_values = nullptr;
  // With tagged faces (spec/FORMAT.md §3.5, 17.0): the bricks' face
  // sections are coded too, each surface face tagged as `faces` says, of a
  // table of `face_tags` tags. The block's region must then reach twice
  // the kept radius farther than the halo above says, or hold the whole
  // level: whether the level keeps the cell across an owned cell's face
  // decides whether the face is on its surface, and that cell's
  // circumsphere may reach two kept radii beyond the owned cell's.
  // `faces_only`: only the face sections (BlockAnalysis::faces and
  // figures.tagged_faces_kept), in a region grown so, apart from the
  // analysis whose choice and build the halo above bounds
  // (bricked_encoder.cpp).
  const FaceTagger* faces = nullptr;
  size_t face_tags = 0;
  bool faces_only = false;
};

struct BlockAnalysis {
  BlockFigures figures;
  // The block's part of the level's surface record (core/level_build.h):
  // owned triangles (grid ids, each sorted), owned surface vertices, and
  // each owned reference boundary vertex's squared distance to the surface.
  std::vector<std::array<uint32_t, 3>> surface_triangles;
  std::vector<uint32_t> surface_vertices;
  std::vector<std::pair<uint32_t, double>> reference_squared;
  // Carving sections of the bricks inside the block (brick, bytes),
  // ascending; with regions, the region sections of those that own a kept
  // cell, with tagged faces the face sections of those that tag a face,
  // and with cell values their cell value sections, and each cell field's
  // bytes in them.
  std::vector<std::pair<uint64_t, std::vector<uint8_t>>> carving, regions, faces, cell_values;
  std::vector<uint64_t> cell_field_bytes;
  std::vector<uint32_t> chosen;                 // owned vertices the coarser level keeps (grid ids)
  std::vector<uint32_t> boundary;               // owned boundary vertices (grid ids)
  std::vector<std::array<uint32_t, 4>> carved;  // with collect_cells: owned kept cells (grid ids)
};

// A block's Delaunay tetrahedralization and, per cell, the reference
// solid's region at its centroid (Solid::verdicts), made by a build.
struct MadeMesh {
  TetMesh dt;
  std::vector<uint8_t> regions;
};
// `reference`: null for level 0 carved by alpha. `made`: the Delaunay
// tetrahedralization of block.points and its regions when a build made
// them already (BlockBuild::mesh; with a reference), taken; null: made
// here. The tetrahedralization is unique and exported in one order
// (mesh/delaunay.h), so the analysis is the same either way.
StatusOr<BlockAnalysis> analyse_block(const BlockRegion& block, BlockReference* reference,
                                      const BlockAnalysisOptions& options, MadeMesh* made = nullptr);

struct BlockBuild {
  std::vector<uint32_t> vertices;  // the coarser level in the region, as the block leaves it (grid ids)
  // Its Delaunay tetrahedralization, vertex i being vertices[i], and per
  // cell the reference solid's region at its centroid: what analysing
  // these points would make again (analyse_block's `made`).
  MadeMesh mesh;
  uint64_t broken = 0;  // owned places still beyond D_max
  bool quality_met = true;
  int rounds = 0;
  // The last check found nothing to repair (BuiltLevel: clean), and the
  // quality's sum and cells it took.
  bool clean = false;
  double quality_sum = 0;
  uint64_t quality_cells = 0;
};
// `fine`: V_l in the region; `keep`: per point of it, whether the coarser
// level holds it now; `record`: the finer level's surface record, its
// reference distances keyed by grid id (ascending).
StatusOr<BlockBuild> build_block(const BlockRegion& fine, std::span<const uint8_t> keep,
                                 const SurfaceRecord& record,
                                 std::span<const std::pair<uint32_t, double>> reference_squared,
                                 BlockReference& reference, const LevelBounds& bounds);

// A block built again where a neighbour put points back need not be: the
// points put back change only the places within reach of them (the
// circumspheres of the cells the level keeps are within two kept radii of
// their corners, and D_max farther for a reference vertex), so a block
// whose last build was clean is built again only if a check of the parts
// of its box within reach of the new points, each in a region of its own
// grown by the halo, finds something to repair there, or the quality over
// the whole box, changed by what those parts hold now against before,
// falls below the floor. Each part is checked as a block is (build_block()
// with no repair round): with the points now, and if clean, before.
struct PartCheck {
  bool clean = false;  // now: nothing beyond D_max, no fin or slot in the part
  double quality_sum_before = 0, quality_sum_now = 0;
  uint64_t quality_cells_before = 0, quality_cells_now = 0;
};
// `part`: V_l in the part's region, owned = the part; `before`, `now`: per
// point of it, whether the coarser level held it at the block's last build
// and holds it now.
StatusOr<PartCheck> check_part(const BlockRegion& part, std::span<const uint8_t> before,
                               std::span<const uint8_t> now, const SurfaceRecord& record,
                               std::span<const std::pair<uint32_t, double>> reference_squared,
                               BlockReference& reference, const LevelBounds& bounds);

// The parts of `box` within `reach` of `points` (grid ids into `all`): the
// cubes of that reach around the points, merged while two meet, each then
// cut to the box; none where no cube meets it. Disjoint.
std::vector<GridBox> parts_near(std::span<const uint32_t> points, std::span<const GridPoint> all,
                                const GridBox& box, int64_t reach, int qbits);

}  // namespace dtm
