// What the layer coder's encoder (layer_encoder.cpp) and decoder
// (layer_decoder.cpp) share: the adaptive model tables and the context
// functions, each the implementation of a rule of spec/FORMAT.md §3.1. Both
// sides must compute them identically; they are written here once.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "bitstream/coordinate_set.h"
#include "bitstream/range_coder.h"
#include "codec/stream/layer_coder.h"

namespace dtm {

// Context layout (spec/FORMAT.md §3.1).
inline constexpr int kKnownClasses = 7;    // class(k): 0, 1, 2, 3-4, 5-8, 9-16, 17+
inline constexpr int kSmallMax = 12;       // n0 of nodes with 2..12 new points: bisection
inline constexpr int kSplitContexts = 29;  // 0: no known point; else 1 + 4 * share bucket + size class
inline constexpr int kBisectNodes = 32;    // heap positions of the bisection of [0, 12]
inline constexpr int kLargeClasses = 33;   // bit_width(n) of nodes with n > 12 (n < 2^32)
inline constexpr int kPrefixBits = 40;     // Exp-Golomb prefix: at most 40 ones
inline constexpr int kReuseContexts = 24;  // floor(2 log2(values in range / values used there)), capped

struct SetCoderModels::Tables {
  AdaptiveBit single[kKnownClasses][kKnownClasses];
  AdaptiveBit small[kSmallMax + 1][kSplitContexts][kBisectNodes];
  AdaptiveBit large_prefix[kLargeClasses][kPrefixBits + 1];
  AdaptiveBit reuse[3][kReuseContexts];
  // Format 3: the grid's qbits, and the values each axis has taken in the
  // stream so far (made at the first point: a stream refused before its
  // first payload costs no memory). Format 2: qbits 0.
  int reuse_qbits = 0;
  std::vector<CoordinateSet> used_sets;

  bool reuses_coordinates() const { return reuse_qbits > 0; }
  std::vector<CoordinateSet>& used() {
    if (used_sets.empty())
      for (int a = 0; a < 3; ++a) used_sets.emplace_back(reuse_qbits);
    return used_sets;
  }
  void note(const GridPoint& p) {
    if (!reuses_coordinates()) return;
    auto& sets = used();
    sets[0].insert(static_cast<uint32_t>(p.x));
    sets[1].insert(static_cast<uint32_t>(p.y));
    sets[2].insert(static_cast<uint32_t>(p.z));
  }
};

namespace layer_coder {

inline int known_class(uint64_t k) {
  if (k <= 2) return static_cast<int>(k);
  if (k <= 4) return 3;
  if (k <= 8) return 4;
  if (k <= 16) return 5;
  return 6;
}

// The share of the known points in the first child, in 7 buckets, and how
// many known points back it: where the coarser level is dense, the finer one
// is too.
inline int split_context(uint64_t k0, uint64_t k) {
  if (k == 0) return 0;
  const int share = static_cast<int>((7 * (2 * k0 + 1)) / (2 * (k + 1)));  // 0..6
  const int size = k <= 1 ? 0 : k <= 4 ? 1 : k <= 16 ? 2 : 3;
  return 1 + 4 * share + size;
}

// n * (k0 + 1/2) / (k + 1), rounded half up: the known points' guess at n0.
inline uint64_t predicted_first(uint64_t n, uint64_t k0, uint64_t k) {
  const unsigned __int128 num = static_cast<unsigned __int128>(n) * (2 * k0 + 1) + (k + 1);
  return static_cast<uint64_t>(num / (2 * (k + 1)));
}

// The context of a lone point's reuse bit: how crowded the node's interval of
// 2^r values is with used ones, b = floor(2 log2(2^r / m)), at most 23.
inline int reuse_context(uint64_t m, int r) {
  const unsigned __int128 range_squared = static_cast<unsigned __int128>(1) << (2 * r);
  int b = 0;
  while (b + 1 < kReuseContexts && (static_cast<unsigned __int128>(m) * m << (b + 1)) <= range_squared) ++b;
  return b;
}

// The bits a lone point has left on each axis at depth d (x is split first).
inline int remaining_bits(int qbits, int depth, int axis) { return qbits - (depth + 2 - axis) / 3; }

inline int32_t axis_of(const GridPoint& p, int axis) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; }

inline uint64_t zigzag(int64_t d) {
  return d >= 0 ? 2 * static_cast<uint64_t>(d) : 2 * static_cast<uint64_t>(-d) - 1;
}
inline int64_t unzigzag(uint64_t u) {
  return (u & 1) ? -static_cast<int64_t>((u + 1) / 2) : static_cast<int64_t>(u / 2);
}

// The first index in [lo, hi) of `codes` whose code is >= mid.
inline size_t split_index(std::span<const MortonCode> codes, size_t lo, size_t hi, MortonCode mid) {
  return static_cast<size_t>(std::lower_bound(codes.begin() + lo, codes.begin() + hi, mid) - codes.begin());
}

}  // namespace layer_coder
}  // namespace dtm
