// The distance from each point of a set to its nearest other point, found
// through a grid of buckets about one spacing wide (exact: integer
// distances): how far apart a level's vertices are, for a bricked level's
// alpha (codec/bricked_encoder.cpp), at about 1 us a point where a kd-tree's
// incremental search took 3 (bunny_10m's level 0: 30 s).
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "common/grid.h"

namespace dtm {

class NearestSpacing {
 public:
  explicit NearestSpacing(std::span<const GridPoint> points);
  // The distance from points[i] to the nearest other point (0 for a lone point).
  double nearest(size_t i) const;

 private:
  struct Cell {
    int64_t x, y, z;
    bool operator==(const Cell&) const = default;
  };
  struct CellHash {
    size_t operator()(const Cell& c) const {
      return static_cast<size_t>((c.x * 73856093) ^ (c.y * 19349663) ^ (c.z * 83492791));
    }
  };
  Cell cell_of(const GridPoint& p) const { return {p.x / side_, p.y / side_, p.z / side_}; }

  std::span<const GridPoint> points_;
  int64_t side_ = 1;
  std::vector<uint32_t> order_;                                              // point indices by cell
  std::unordered_map<Cell, std::pair<uint32_t, uint32_t>, CellHash> cells_;  // a cell's range of order_
  int64_t rings_ = 1;                                                        // enough to reach every cell
};

}  // namespace dtm
