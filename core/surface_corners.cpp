#include "core/surface_corners.h"

#include <algorithm>

#include "common/parallel_for.h"
#include "common/parallel_sort.h"

namespace dtm {

SurfaceCorners surface_corners(std::span<const GridPoint> vertices,
                               std::span<const std::array<uint32_t, 3>> triangles) {
  constexpr size_t kRange = 8192;  // items per range of the loops on every core
  SurfaceCorners s;
  std::vector<uint32_t> used(3 * triangles.size());
  parallel_ranges(triangles.size(), kRange, [&](size_t first, size_t last) {
    for (size_t t = first; t < last; ++t)
      for (size_t i = 0; i < 3; ++i) used[3 * t + i] = triangles[t][i];
  });
  parallel_sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  s.corners.resize(used.size());
  parallel_ranges(used.size(), kRange, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) s.corners[k] = vertices[used[k]];
  });
  s.triangles.resize(triangles.size());
  const auto corner = [&](uint32_t v) {
    return static_cast<uint32_t>(std::lower_bound(used.begin(), used.end(), v) - used.begin());
  };
  parallel_ranges(triangles.size(), kRange, [&](size_t first, size_t last) {
    for (size_t t = first; t < last; ++t)
      s.triangles[t] = {corner(triangles[t][0]), corner(triangles[t][1]), corner(triangles[t][2])};
  });
  return s;
}

}  // namespace dtm
