// Morton codes' bit shuffles: the 21 low bits of a number moved to every
// third bit, and back (codec/stream/layer_coder.cpp's codes of grid
// points; core/triangle_distance_tree.cpp's order of triangles).
#pragma once

#include <cstdint>

namespace dtm {

// The 21 low bits of v moved to every third bit (bit i to bit 3i).
inline uint64_t spread_by_three(uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

// The inverse: every third bit (from bit 0) gathered into the low 21.
inline uint64_t gather_by_three(uint64_t v) {
  v &= 0x1249249249249249ull;
  v = (v ^ (v >> 2)) & 0x10c30c30c30c30c3ull;
  v = (v ^ (v >> 4)) & 0x100f00f00f00f00full;
  v = (v ^ (v >> 8)) & 0x1f0000ff0000ffull;
  v = (v ^ (v >> 16)) & 0x1f00000000ffffull;
  v = (v ^ (v >> 32)) & 0x1fffffull;
  return v;
}

}  // namespace dtm
