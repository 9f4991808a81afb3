#include "core/nearest_spacing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace dtm {

NearestSpacing::NearestSpacing(std::span<const GridPoint> points) : points_(points) {
  if (points.empty()) return;
  GridPoint lo = points[0], hi = points[0];
  for (const GridPoint& p : points) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  // Cells of about one point each over the bounding box (more where the
  // points fill only part of it).
  const double volume = (hi.x - lo.x + 1.0) * (hi.y - lo.y + 1.0) * (hi.z - lo.z + 1.0);
  side_ = std::max<int64_t>(1, static_cast<int64_t>(std::cbrt(volume / static_cast<double>(points.size()))));
  rings_ = (std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) + side_) / side_ + 1;
  std::vector<std::pair<Cell, uint32_t>> by_cell(points.size());
  for (uint32_t i = 0; i < points.size(); ++i) by_cell[i] = {cell_of(points[i]), i};
  std::sort(by_cell.begin(), by_cell.end(), [](const auto& a, const auto& b) {
    return std::tie(a.first.x, a.first.y, a.first.z, a.second) <
           std::tie(b.first.x, b.first.y, b.first.z, b.second);
  });
  order_.reserve(points.size());
  cells_.reserve(points.size());
  for (uint32_t k = 0; k < by_cell.size(); ++k) {
    order_.push_back(by_cell[k].second);
    auto [it, fresh] = cells_.try_emplace(by_cell[k].first, k, k + 1);
    if (!fresh) it->second.second = k + 1;
  }
}

double NearestSpacing::nearest(size_t i) const {
  const GridPoint& p = points_[i];
  const Cell c = cell_of(p);
  int64_t best = std::numeric_limits<int64_t>::max();
  for (int64_t r = 0; r <= rings_; ++r) {
    // The cells r steps away (the shell of the cube of side 2r + 1).
    for (int64_t dx = -r; dx <= r; ++dx)
      for (int64_t dy = -r; dy <= r; ++dy)
        for (int64_t dz = -r; dz <= r; ++dz) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
          const auto it = cells_.find({c.x + dx, c.y + dy, c.z + dz});
          if (it == cells_.end()) continue;
          for (uint32_t k = it->second.first; k < it->second.second; ++k) {
            const uint32_t j = order_[k];
            if (j == i) continue;
            const GridPoint& q = points_[j];
            const int64_t ex = q.x - p.x, ey = q.y - p.y, ez = q.z - p.z;
            best = std::min(best, ex * ex + ey * ey + ez * ez);
          }
        }
    // Every point of a farther cell is more than r sides away.
    if (best <= (r * side_) * (r * side_)) break;
  }
  return best == std::numeric_limits<int64_t>::max() ? 0 : std::sqrt(static_cast<double>(best));
}

}  // namespace dtm
