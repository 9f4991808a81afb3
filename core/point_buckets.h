// A fixed set of points found by box or ball: a uniform grid of buckets
// (CSR). The codec's repair asks it which removed vertices lie in a cell's
// circumsphere.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/csr.h"
#include "common/grid.h"

namespace dtm {

class PointBuckets {
 public:
  // About one point per bucket, for points that fill a volume.
  explicit PointBuckets(std::span<const GridPoint> points);

  // Calls f(i) for every point i within `radius` of `center` (grid units).
  template <class F>
  void for_each_in_ball(const std::array<double, 3>& center, double radius, F&& f) const {
    const double r2 = radius * radius;
    for_each_in_box({center[0] - radius, center[1] - radius, center[2] - radius},
                    {center[0] + radius, center[1] + radius, center[2] + radius}, [&](uint32_t i) {
                      const GridPoint& p = points_[i];
                      const double dx = p.x - center[0], dy = p.y - center[1], dz = p.z - center[2];
                      if (dx * dx + dy * dy + dz * dz < r2) f(i);
                    });
  }

  // Calls f(i) for every point i inside the box [lo, hi] (grid units,
  // inclusive), each once.
  template <class F>
  void for_each_in_box(const std::array<double, 3>& lo, const std::array<double, 3>& hi, F&& f) const {
    if (points_.empty()) return;
    std::array<int64_t, 3> b0, b1;
    for (int a = 0; a < 3; ++a) {
      b0[a] = bucket_coordinate(lo[a], a);
      b1[a] = bucket_coordinate(hi[a], a);
    }
    for (int64_t z = b0[2]; z <= b1[2]; ++z)
      for (int64_t y = b0[1]; y <= b1[1]; ++y)
        for (int64_t x = b0[0]; x <= b1[0]; ++x)
          for (uint32_t i : buckets_.row(static_cast<size_t>((z * dims_[1] + y) * dims_[0] + x))) {
            const GridPoint& p = points_[i];
            if (p.x >= lo[0] && p.x <= hi[0] && p.y >= lo[1] && p.y <= hi[1] && p.z >= lo[2] && p.z <= hi[2])
              f(i);
          }
  }

 private:
  int64_t bucket_coordinate(double c, int axis) const;

  std::vector<GridPoint> points_;
  std::array<int64_t, 3> origin_{}, dims_{1, 1, 1};
  int64_t size_ = 1;  // bucket edge, grid units
  Csr buckets_;
};

}  // namespace dtm
