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
};

struct EncodedStream {
  std::vector<uint8_t> bytes;
  // Bytes of each level's layer (header included), indexed by level.
  std::vector<uint64_t> layer_bytes;
};

// `points` are the grid points the hierarchy's vertex indices refer to.
EncodedStream encode_stream(const Hierarchy& hierarchy, std::span<const GridPoint> points,
                            const Grid& grid, AlphaPolicy::Kind alpha_policy,
                            const EncoderOptions& options = {});

}  // namespace dtm
