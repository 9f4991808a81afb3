#include "core/point_buckets.h"

#include <algorithm>
#include <cmath>

namespace dtm {

PointBuckets::PointBuckets(std::span<const GridPoint> points) : points_(points.begin(), points.end()) {
  if (points_.empty()) return;
  std::array<int64_t, 3> lo = {points_[0].x, points_[0].y, points_[0].z}, hi = lo;
  for (const GridPoint& p : points_) {
    const std::array<int64_t, 3> c = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  }
  origin_ = lo;
  const int64_t extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}) + 1;
  // cbrt(n) buckets along the box's largest side.
  const double per_side = std::max(1.0, std::cbrt(static_cast<double>(points_.size())));
  size_ = std::max<int64_t>(1, static_cast<int64_t>(static_cast<double>(extent) / per_side));
  for (int a = 0; a < 3; ++a) dims_[a] = (hi[a] - lo[a]) / size_ + 1;
  buckets_ = build_csr(static_cast<size_t>(dims_[0] * dims_[1] * dims_[2]), [&](auto&& emit) {
    for (uint32_t i = 0; i < points_.size(); ++i) {
      const GridPoint& p = points_[i];
      const int64_t x = (p.x - origin_[0]) / size_, y = (p.y - origin_[1]) / size_,
                    z = (p.z - origin_[2]) / size_;
      emit(static_cast<uint32_t>((z * dims_[1] + y) * dims_[0] + x), i);
    }
  });
}

int64_t PointBuckets::bucket_coordinate(double c, int axis) const {
  const double b = std::floor((c - static_cast<double>(origin_[axis])) / static_cast<double>(size_));
  return std::clamp<int64_t>(static_cast<int64_t>(std::clamp(b, -1.0, 1e12)), 0, dims_[axis] - 1);
}

}  // namespace dtm
