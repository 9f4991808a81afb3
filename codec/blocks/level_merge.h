// A bricked level's results put together from its blocks' analyses
// (codec/blocks/block_levels.h), in block order, so that the sums, and so
// the figures and the stream, are the same for any number of ranks.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
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

}  // namespace dtm
