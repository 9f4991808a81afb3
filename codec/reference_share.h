// The input's tetrahedra shared out among the ranks of a run while the
// reference is made (codec/bricked_encoder.h), so that no rank holds them
// all: the grid points in one range of ids per rank (quantize()'s order,
// along x first: each range a slab), and a rank holds a tetrahedron when the
// least or the second least of its corners is in its range. Every face's
// least corner is one of those two, so the rank holds every tetrahedron
// around a face whose least corner is in its range, and tells on its own
// whether that face is on the boundary. A tetrahedron is its rank's own
// (counted and listed once over the ranks) by its least corner.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>

namespace dtm {

class ReferenceShare {
 public:
  ReferenceShare(size_t points, int rank, int ranks) : points_(points), rank_(rank), ranks_(ranks) {}

  // The first grid id of rank r's range (r = ranks: the end).
  uint64_t first(int r) const { return points_ * static_cast<uint64_t>(r) / static_cast<uint64_t>(ranks_); }
  bool mine(uint32_t point) const { return point >= first(rank_) && point < first(rank_ + 1); }
  // Whether this rank holds t, and whether t is its own.
  bool holds(const std::array<uint32_t, 4>& t) const {
    const auto [least, second] = two_least(t);
    return mine(least) || mine(second);
  }
  bool owns(const std::array<uint32_t, 4>& t) const { return mine(two_least(t).first); }

 private:
  static std::pair<uint32_t, uint32_t> two_least(const std::array<uint32_t, 4>& t) {
    uint32_t a = std::min(t[0], t[1]), b = std::max(t[0], t[1]);
    for (int k = 2; k < 4; ++k)
      if (t[k] < a)
        b = a, a = t[k];
      else if (t[k] < b)
        b = t[k];
    return {a, b};
  }

  uint64_t points_;
  int rank_, ranks_;
};

}  // namespace dtm
