// A bricked level's results put together from its blocks' analyses
// (codec/blocks/block_levels.h), in block order, so that the sums, and so
// the figures and the stream, are the same for any number of ranks.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "codec/blocks/block_levels.h"
#include "codec/blocks/bricked_stream_writer.h"
#include "core/level_build.h"

namespace dtm {

struct MergedLevel {
  SurfaceRecord record;                                        // the level's surface, ascending
  std::vector<std::pair<uint32_t, double>> reference_squared;  // ascending by grid id
  std::vector<uint32_t> boundary;                              // the boundary vertices, ascending
  std::vector<std::array<uint32_t, 4>> carved;  // level 0's kept cells, when the blocks collected them
  // The reference's boundary vertices measured, when the level was
  // measured against a reference.
  std::optional<uint64_t> reference_boundary_vertices;
  // The cells inside the reference solid thicker than D_max that the kept
  // radius dropped, and the largest circumradius among them (BlockFigures).
  uint64_t dropped_thick = 0;
  double dropped_thick_radius = 0;
};

// Adds the blocks' figures to `out` (its stats' boundary vertices,
// tetrahedra, quality and shape, its cell hash and carving) and merges the
// rest. Each analysis is left with its figures and choice only, the rest
// freed as it is merged.
MergedLevel merge_blocks(std::vector<BlockAnalysis>& analysis, int level, BrickedLevel& out);

// What a block's build left of the coarser level's quality over the cells
// it owns (BlockBuild), and its floor there.
struct BlockQuality {
  bool met = true;  // the block's own average at least its floor
  double sum = 0;   // of its owned kept cells' smallest solid angles
  uint64_t cells = 0;
  double floor = 0;
};
// Whether the coarser level keeps its quality floor: every block met its
// own, or else the level's cells together do, the sum of their quality at
// least the sum of their blocks' floors, each counted once a cell (summed
// in block order: the same for any number of ranks). A block owning a few
// cells at the solid's edge can miss its floor with nothing near to put
// back (bunny_1m in blocks of 2^14 points: 3 cells averaging 0.19
// against 0.22, one block of 50); that alone must not make the finer
// level the coarsest, as it would not in a level built whole.
bool level_quality_met(std::span<const BlockQuality> blocks);

}  // namespace dtm
