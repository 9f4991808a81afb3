// A fixed set of points visited in order of distance from a query point
// (CGAL's incremental neighbour search on a kd-tree). The codec's repair asks
// it for the removed vertices nearest a cell's circumcentre: for a flat cell
// that centre lies far from every point, and a search by buckets would walk
// most of the model's grid to find the few nearest.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>

#include "common/grid.h"

namespace dtm {

class NearestPoints {
 public:
  explicit NearestPoints(std::span<const GridPoint> points);
  ~NearestPoints();
  NearestPoints(const NearestPoints&) = delete;
  NearestPoints& operator=(const NearestPoints&) = delete;

  // Calls visit(i, d2) for the points i in increasing squared distance d2
  // from `centre` (as the search computes it; equal distances in any order)
  // until visit returns false or every point was visited. Safe to call from
  // several threads at once.
  void visit_nearest(const std::array<double, 3>& centre,
                     const std::function<bool(uint32_t, double)>& visit) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace dtm
