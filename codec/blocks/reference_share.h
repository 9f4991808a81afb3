// The input's tetrahedra shared out among the ranks of a run while the
// reference is made (codec/blocks/bricked_encoder.h), so that no rank holds them
// all: the grid points cut into one run of Morton order per rank, of about
// equal counts (the blocks of level 0 are shared out in Morton order too, so
// a rank mostly holds the reference where it builds), and a rank holds a
// tetrahedron when the least or the second least of its corners (by grid
// id) is in its run. Every face's least corner is one of those two, so the
// rank holds every tetrahedron around a face whose least corner is its own,
// and tells on its own whether that face is on the boundary. A tetrahedron
// is its rank's own (counted and listed once over the ranks) by its least
// corner.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "common/grid.h"

namespace dtm {

class ReferenceShare {
 public:
  // Rank `rank` of `ranks`' share of `points` (which must outlive it), on a
  // grid of `qbits` bits: every rank computes the same cuts.
  ReferenceShare(std::span<const GridPoint> points, int qbits, int rank, int ranks);

  bool mine(uint32_t point) const {
    const uint64_t k = key(points_[point]);
    return k >= lo_ && (last_ || k < hi_);
  }
  // Whether this rank holds t, and whether t is its own.
  bool holds(const std::array<uint32_t, 4>& t) const {
    const auto [least, second] = two_least(t);
    return mine(least) || mine(second);
  }
  bool owns(const std::array<uint32_t, 4>& t) const { return mine(two_least(t).first); }
  // The ranks that hold t (its corners' ids into the points): those of its
  // two least corners, as holds() says on each rank (meshenc sends each
  // tetrahedron it read to them).
  std::array<int, 2> holding_ranks(const std::array<uint32_t, 4>& t) const {
    const auto [least, second] = two_least(t);
    return {rank_of(least), rank_of(second)};
  }
  // The rank whose run holds the point (every rank computes the same cuts):
  // a tetrahedron is held by the ranks of its two least corners, where a
  // rank that read it sends it (meshenc reads an .ele in parts).
  int rank_of(uint32_t point) const {
    return static_cast<int>(std::upper_bound(cuts_.begin(), cuts_.end(), key(points_[point])) -
                            cuts_.begin());
  }

 private:
  // A point's place in Morton order: its code's top 64 bits (points that
  // share them go to one rank).
  uint64_t key(const GridPoint& p) const;
  static std::pair<uint32_t, uint32_t> two_least(const std::array<uint32_t, 4>& t) {
    uint32_t a = std::min(t[0], t[1]), b = std::max(t[0], t[1]);
    for (int k = 2; k < 4; ++k)
      if (t[k] < a)
        b = a, a = t[k];
      else if (t[k] < b)
        b = t[k];
    return {a, b};
  }

  std::span<const GridPoint> points_;
  int qbits_;
  uint64_t lo_ = 0, hi_ = 0;    // this rank's keys: [lo_, hi_), or from lo_ on for the last
  std::vector<uint64_t> cuts_;  // where ranks 1, 2, ... begin
  bool last_ = true;
};

}  // namespace dtm
