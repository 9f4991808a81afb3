// Hierarchy -> .dtm bytes: the header, then one layer per level, coarsest
// first, each holding the positions of the vertices that level adds.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/grid.h"
#include "core/hierarchy.h"

namespace dtm {

struct EncoderOptions {
  // Store each level's canonical cell-set hash, so that a decoder built
  // against another CGAL can prove it rebuilt the same meshes (meshdec --verify).
  bool cell_hashes = false;
  // Stream every level_step-th level of the hierarchy (levels 0, s, 2s, ...)
  // and its coarsest: fewer, larger layers cost fewer bits (each layer's
  // points are coded given the coarser ones, and deciding which layer a point
  // belongs to is what costs) at the price of fewer levels of detail. The
  // stream numbers its levels 0, 1, 2, ... in that order.
  int level_step = 1;
};

struct EncodedStream {
  std::vector<uint8_t> bytes;
  // Bytes of each hierarchy level's layer (header included), indexed by
  // hierarchy level; 0 for a level left out by level_step.
  std::vector<uint64_t> layer_bytes;
  // The hierarchy level of each stream level (finest first).
  std::vector<int> streamed_levels;
};

// `points` are the grid points the hierarchy's vertex indices refer to.
EncodedStream encode_stream(const Hierarchy& hierarchy, std::span<const GridPoint> points,
                            const Grid& grid, AlphaPolicy::Kind alpha_policy,
                            const EncoderOptions& options = {});

}  // namespace dtm
