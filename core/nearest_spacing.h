// The distance from each point of a set to its nearest other point, found
// through a grid of buckets about one spacing wide (exact: integer
// distances): how far apart a level's vertices are, for a bricked level's
// alpha (codec/blocks/bricked_encoder.cpp), at about 1 us a point where a kd-tree's
// incremental search took 3 (bunny_10m's level 0: 30 s).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"

namespace dtm {

class NearestSpacing {
 public:
  explicit NearestSpacing(std::span<const GridPoint> points);
  // The points points[ids[i]] (both the caller's, which must outlive this):
  // a level's, without a copy of them.
  NearestSpacing(std::span<const GridPoint> points, std::span<const uint32_t> ids);
  // The distance from the i-th point to the nearest other one (0 for a lone point).
  double nearest(size_t i) const;

 private:
  struct Cell {
    int32_t x, y, z;
    auto operator<=>(const Cell&) const = default;  // NOLINT(modernize-use-nullptr): clang-tidy 14 bug
  };
  Cell cell_of(const GridPoint& p) const {
    return {static_cast<int32_t>(p.x / side_), static_cast<int32_t>(p.y / side_),
            static_cast<int32_t>(p.z / side_)};
  }

  const GridPoint& at(size_t i) const { return ids_.empty() ? points_[i] : points_[ids_[i]]; }

  std::span<const GridPoint> points_;
  std::span<const uint32_t> ids_;  // empty: all of points_
  int64_t side_ = 1;
  // The occupied cells, ascending (x, then y, then z), each with its first
  // point in order_ (one more at the end): 20 bytes a point, where a hash
  // map of cells took 50 and sorting (cell, point) pairs 32 more (bunny_10m's
  // level 0: 1.45 GB of the encoder's peak).
  std::vector<Cell> cells_;
  std::vector<uint32_t> first_;
  std::vector<uint32_t> order_;  // point indices by cell
  int64_t rings_ = 1;            // enough to reach every cell
};

}  // namespace dtm
