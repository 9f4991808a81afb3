#include "core/nearest_spacing.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/parallel_for.h"
#include "common/parallel_sort.h"

namespace dtm {

NearestSpacing::NearestSpacing(std::span<const GridPoint> points) : NearestSpacing(points, {}) {}

NearestSpacing::NearestSpacing(std::span<const GridPoint> points, std::span<const uint32_t> ids)
    : points_(points), ids_(ids) {
  const size_t n = ids.empty() ? points.size() : ids.size();
  if (n == 0) return;
  GridPoint lo = at(0), hi = at(0);
  for (size_t i = 0; i < n; ++i) {
    const GridPoint& p = at(i);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  // Cells of about one point each over the bounding box (more where the
  // points fill only part of it).
  const double volume = (hi.x - lo.x + 1.0) * (hi.y - lo.y + 1.0) * (hi.z - lo.z + 1.0);
  side_ = std::max<int64_t>(1, static_cast<int64_t>(std::cbrt(volume / static_cast<double>(n))));
  rings_ = (std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) + side_) / side_ + 1;
  // The points by cell (then index: the keys are distinct, so any sort
  // gives this order), each one's cell found once, sorted on every core.
  order_.resize(n);
  // The cells and each one's first place in order_, given the cell of each
  // place in order: as many cells as are occupied, reserved at once (grown
  // by doubling, about one a point, they were held up to three times over
  // while copied).
  const auto fill_cells = [&](const auto& cell_at) {
    size_t occupied = 0;
    for (uint32_t k = 0; k < n; ++k) occupied += k == 0 || cell_at(k) != cell_at(k - 1);
    cells_.reserve(occupied);
    first_.reserve(occupied + 1);
    for (uint32_t k = 0; k < n; ++k)
      if (const Cell c = cell_at(k); cells_.empty() || cells_.back() != c)
        cells_.push_back(c), first_.push_back(k);
  };
  const int64_t top = std::max({hi.x, hi.y, hi.z}) / side_;
  if (std::min({lo.x, lo.y, lo.z}) >= 0 && top < (int64_t{1} << 21)) {
    // Each cell packed in 8 bytes (x, then y, then z: the same order), the
    // indices sorted by them: 12 bytes a point while sorting, where the
    // cell and index side by side took 16 and the order 4 more (with the
    // cells grown by doubling, bunny_10m's level 0 alpha added 265 MiB to
    // what each MPI rank held).
    constexpr uint64_t kMask = (uint64_t{1} << 21) - 1;
    std::vector<uint64_t> key(n);
    parallel_ranges(n, 16384, [&](size_t first, size_t last) {
      for (size_t i = first; i < last; ++i) {
        const Cell c = cell_of(at(i));
        key[i] =
            static_cast<uint64_t>(c.x) << 42 | static_cast<uint64_t>(c.y) << 21 | static_cast<uint64_t>(c.z);
      }
    });
    for (uint32_t k = 0; k < n; ++k) order_[k] = k;
    parallel_sort(order_.begin(), order_.end(),
                  [&](uint32_t a, uint32_t b) { return key[a] != key[b] ? key[a] < key[b] : a < b; });
    fill_cells([&](uint32_t k) {
      const uint64_t c = key[order_[k]];
      return Cell{static_cast<int32_t>(c >> 42), static_cast<int32_t>((c >> 21) & kMask),
                  static_cast<int32_t>(c & kMask)};
    });
  } else {
    struct Keyed {
      Cell cell;
      uint32_t i;
      bool operator<(const Keyed& o) const { return cell != o.cell ? cell < o.cell : i < o.i; }
    };
    std::vector<Keyed> keyed(n);
    parallel_ranges(n, 16384, [&](size_t first, size_t last) {
      for (size_t i = first; i < last; ++i) keyed[i] = {cell_of(at(i)), static_cast<uint32_t>(i)};
    });
    parallel_sort(keyed.begin(), keyed.end());
    for (uint32_t k = 0; k < n; ++k) order_[k] = keyed[k].i;
    fill_cells([&](uint32_t k) { return keyed[k].cell; });
  }
  first_.push_back(static_cast<uint32_t>(order_.size()));
}

double NearestSpacing::nearest(size_t i) const {
  const GridPoint& p = at(i);
  const Cell c = cell_of(p);
  int64_t best = std::numeric_limits<int64_t>::max();
  for (int64_t r = 0; r <= rings_; ++r) {
    // The cells r steps away (the shell of the cube of side 2r + 1): per
    // column (dx, dy), its cells from dz = -r to r are one run of cells_.
    for (int64_t dx = -r; dx <= r; ++dx)
      for (int64_t dy = -r; dy <= r; ++dy) {
        const bool side = std::max(std::abs(dx), std::abs(dy)) == r;
        const Cell from{static_cast<int32_t>(c.x + dx), static_cast<int32_t>(c.y + dy),
                        static_cast<int32_t>(c.z - r)};
        for (auto it = std::lower_bound(cells_.begin(), cells_.end(), from);
             it != cells_.end() && it->x == from.x && it->y == from.y && it->z <= c.z + r; ++it) {
          if (!side && std::abs(it->z - c.z) != r) continue;  // inside the shell: seen before
          const size_t cell = static_cast<size_t>(it - cells_.begin());
          for (uint32_t k = first_[cell]; k < first_[cell + 1]; ++k) {
            const uint32_t j = order_[k];
            if (j == i) continue;
            const GridPoint& q = at(j);
            const int64_t ex = q.x - p.x, ey = q.y - p.y, ez = q.z - p.z;
            best = std::min(best, ex * ex + ey * ey + ez * ez);
          }
        }
      }
    // Every point of a farther cell is more than r sides away.
    if (best <= (r * side_) * (r * side_)) break;
  }
  return best == std::numeric_limits<int64_t>::max() ? 0 : std::sqrt(static_cast<double>(best));
}

}  // namespace dtm
