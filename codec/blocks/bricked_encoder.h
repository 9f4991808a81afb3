// A bricked stream (format 8.0, spec/FORMAT.md §3.5) from grid points, its
// levels built block by block (codec/blocks/block_levels.h, spec/HIERARCHY.md
// §6.5) on one process or on the ranks of an MPI run: each rank builds the
// blocks it is given and the ranks exchange what the blocks found, level
// after level. The blocks, and so the stream, depend on the points alone:
// the bytes are the same for any number of ranks, and each block's work
// holds only its region in memory.
//
// What a rank holds whole: the grid points (12 bytes each), which level
// each belongs to, a Morton index of them (4 bytes each), the reference's
// boundary triangles and which grid cells lie inside, and what the blocks
// report (the surface records, the carving sections, the coarser
// level's choice); the Delaunay tetrahedralizations, the carving and the
// checks are made block by block. The input's tetrahedra are held in
// shares (codec/blocks/reference_share.h): each rank finds its own part of the
// boundary (the ranks gather the boundary) and keeps its tetrahedra near it
// as its part of the solid; what a block's part cannot answer, the other
// ranks answer while they work (codec/blocks/reference_questions.h).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "codec/sections/region_coder.h"
#include "codec/sections/value_fields.h"
#include "common/exchange.h"
#include "common/grid.h"
#include "common/status.h"
#include "core/face_tags.h"
#include "core/hierarchy.h"
#include "core/solid.h"
#include "mesh/carving.h"

namespace dtm {

class ReferenceShare;

struct BrickedEncodeOptions {
  // The levels (HierarchyOptions' meaning, lengths in grid units): dmax,
  // average_quality_floor, removal_share, max_levels, min_base_vertices,
  // stop_when_boundary_is_final, on_phase. alpha: kPaper (alpha from the
  // level's spacing, §6.5) or kFixed.
  HierarchyOptions hierarchy;
  // Each layer's bricks hold about brick_points of its new points; the
  // levels are built in blocks of about block_points points.
  uint64_t brick_points = 2048;
  uint64_t block_points = uint64_t{1} << 18;
  // How many blocks a process builds at once, each on its share of the
  // threads; 0: one per thread, as many as a quarter of the process's share
  // of the machine's memory holds. Each holds its region's work (about 1 KB
  // a block point: bunny_1m's blocks of up to 228,640 points, about 230
  // MiB), so the memory a process needs grows with it; the stream does not
  // depend on it.
  int blocks_at_once = 0;
  bool cell_hashes = false;
  // A block whose last build was clean is checked where a neighbour put
  // points back rather than built again (check_part(), block_levels.h);
  // false: built again (the same stream, slower; for tests).
  bool check_parts = true;
  // A level built in one block is analysed from the build's
  // tetrahedralization (the same stream; false, for tests: made again).
  bool reuse_build_mesh = true;
  // BrickedEncoding::decode_order made (false: left empty, 4 bytes a point
  // less while the finest layer is written).
  bool decode_order = true;
  // The ranks of the run; nullptr: this process alone.
  RankExchange* exchange = nullptr;
};

struct BrickedEncodeInput {
  std::span<const GridPoint> points;  // distinct grid points, ascending (quantize()'s order)
  Grid grid;                          // as the stream holds it (the input's units)
  // The reference solid's tetrahedra (indices into points), or none.
  std::span<const std::array<uint32_t, 4>> reference_tets;
  // Their regions (materials): per tetrahedron 1 + the index of its region
  // in `regions`, the stream's region table (spec/FORMAT.md §2.2; format
  // 15.0: every level's kept cells carry theirs). Empty: one region, no
  // table; with one region, `regions` may name it (every section empty).
  // On ranks, those of the tetrahedra the rank was given (its share, or all
  // of them with cell_values), of which it keeps its share for its
  // reference in parts.
  std::span<const uint8_t> reference_regions;
  std::span<const RegionLabel> regions;
  // Called once reference_tets are read no more (the encoder's solid and
  // boundary hold what it needs of them): before the levels are built, or
  // with cell_values once level 1 is (level 0's cells then coded).
  std::function<void()> reference_tets_done;
  // On ranks: the share the tetrahedra were cut by (codec/blocks/reference_share.h,
  // its points these), or nullptr: made from the exchange.
  const ReferenceShare* share = nullptr;
  // A scan's voxels as the solid (without tetrahedra), or nullptr; with
  // neither, level 0's alpha carving is the reference.
  const Solid* voxels = nullptr;
  // The per-vertex values (indexed by point), or nullptr: each chunk then
  // carries its points' values (spec/FORMAT.md §3.5).
  const FieldSectionEncoder* values = nullptr;
  // Per-cell values (indexed by reference tetrahedron), or nullptr: each of
  // level 0's chunks then carries its kept cells' values, each cell taking
  // those of the input tetrahedron core/cell_sources.h finds for it
  // (format 16.0, spec/FORMAT.md §3.5). On ranks, every rank must be given
  // every tetrahedron and these values of them all (kInvalidInput if the
  // ranks' tetrahedra do not add up so), not its share: a cell's source is
  // looked for among all the tetrahedra at its corners, which are held until
  // level 1 is built (level 0's cells then coded); these values are read
  // until the stream is written.
  const FieldSectionEncoder* cell_values = nullptr;
  // Tagged faces: what tags each level's surface faces (core/face_tags.h:
  // made of every input tetrahedron's surface and every tagged triangle)
  // and the table of the tags, or nullptr: each chunk then codes its kept
  // cells' surface faces' tags (format 17.0, spec/FORMAT.md §3.5). On
  // ranks, as cell_values: every rank given every tetrahedron.
  const FaceTagger* faces = nullptr;
  std::span<const RegionLabel> face_tags;
};

struct BrickedEncoding {
  std::vector<uint8_t> bytes;      // the stream, on every rank
  std::vector<LevelStats> levels;  // finest first
  std::vector<uint64_t> layer_bytes, carving_bytes, value_bytes, region_bytes, face_bytes, chunk_count,
      index_bytes;                                       // per level
  std::vector<std::vector<uint64_t>> level_field_bytes;  // per level, per field
  uint64_t field_table_bytes = 0, region_table_bytes = 0, face_table_bytes = 0, cell_field_table_bytes = 0;
  uint64_t tagged_faces_kept = 0;  // with tagged faces: the input's among level 0's tagged faces
  // With cell data: level 0's cell value sections' bytes, each field's
  // share, and where the kept cells' values came from (BlockFigures).
  uint64_t cell_value_bytes = 0;
  std::vector<uint64_t> cell_field_bytes;
  uint64_t cells_from_input = 0, cells_from_nearest = 0;
  std::vector<int> brick_depth;        // per level
  std::vector<uint32_t> decode_order;  // as EncodedStream's
  uint64_t reference_boundary_vertices = 0;
  uint64_t reference_questions = 0, reference_question_runs = 0,
           reference_questions_at_once = 0;                       // as EncodeReport's
  uint64_t blocks_built_again = 0, blocks_checked_in_parts = 0;   // as EncodeReport's
  uint64_t levels_analysed_from_build = 0;                        // as EncodeReport's
  double level0_spacing_kept_radius = 0, level0_kept_radius = 0;  // as EncodeReport's
  uint64_t level0_cells_dropped = 0;                              // as EncodeReport's
};

StatusOr<BrickedEncoding> encode_bricked(const BrickedEncodeInput& input, const BrickedEncodeOptions& options,
                                         const std::function<void(const LevelStats&)>& on_level = {});

}  // namespace dtm
