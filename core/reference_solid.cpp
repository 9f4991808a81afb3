#include "core/reference_solid.h"

#include <algorithm>
#include <cmath>

#include "common/csr.h"
#include "mesh/geometry.h"

namespace dtm {
namespace {

using P4 = std::array<int64_t, 3>;

// Sign of the orientation determinant of (a, b, c, d), exact: coordinates
// at 4x scale need 27 bits, differences 28, triple products 84. With
// coordinates under 2^18 (q <= 16) differences are under 2^19 and the
// determinant under 3 x 2^58: 64 bits hold it, and it is 3x faster.
template <class Int>
int orientation_in(const P4& a, const P4& b, const P4& c, const P4& d) {
  const Int ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const Int vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const Int wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
  const Int det = ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx);
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}
constexpr auto orientation64 = orientation_in<int64_t>;
constexpr auto orientation = orientation_in<Int128>;

P4 times4(const GridPoint& p) { return {4 * int64_t{p.x}, 4 * int64_t{p.y}, 4 * int64_t{p.z}}; }

}  // namespace

ReferenceSolid::ReferenceSolid(std::span<const GridPoint> points,
                               std::span<const std::array<uint32_t, 4>> cells) {
  tets_.reserve(cells.size());
  for (const auto& c : cells) {
    std::array<P4, 4> t = {times4(points[c[0]]), times4(points[c[1]]), times4(points[c[2]]),
                           times4(points[c[3]])};
    const int o = orientation(t[0], t[1], t[2], t[3]);
    if (o == 0) continue;
    if (o < 0) std::swap(t[2], t[3]);
    tets_.push_back(t);
  }
  if (tets_.empty()) return;
  lo_ = hi_ = tets_[0][0];
  boxes_.reserve(tets_.size());
  for (const auto& t : tets_) {
    P4 tlo = t[0], thi = t[0];
    for (const P4& p : t)
      for (int a = 0; a < 3; ++a) {
        tlo[a] = std::min(tlo[a], p[a]), thi[a] = std::max(thi[a], p[a]);
        lo_[a] = std::min(lo_[a], p[a]), hi_[a] = std::max(hi_[a], p[a]);
      }
    boxes_.push_back({tlo, thi});
  }
  const int64_t largest = std::max({hi_[0] - lo_[0], hi_[1] - lo_[1], hi_[2] - lo_[2]}) + 1;
  const double cube_root = std::cbrt(static_cast<double>(tets_.size()));
  small_ = std::max({std::abs(lo_[0]), std::abs(lo_[1]), std::abs(lo_[2]), std::abs(hi_[0]), std::abs(hi_[1]),
                     std::abs(hi_[2])}) < (int64_t{1} << 18);
  // A graded mesh's cells range from tiny (at the surface) to large (inside):
  // buckets of half the spacing N tetrahedra would have spread evenly over
  // the box (about 8 N buckets), so that the small cells, where most queries
  // fall, share few buckets; a large cell is listed in many.
  bucket_size_ = std::max<int64_t>(1, static_cast<int64_t>(static_cast<double>(largest) / (2 * cube_root)));
  for (int a = 0; a < 3; ++a) dims_[a] = (hi_[a] - lo_[a]) / bucket_size_ + 1;
  sort_along_morton_curve();
  const size_t buckets = static_cast<size_t>(dims_[0] * dims_[1] * dims_[2]);
  auto for_each_bucket = [&](const std::array<P4, 2>& box, auto&& f) {
    const P4 &tlo = box[0], &thi = box[1];
    std::array<int64_t, 3> b0, b1;
    for (int a = 0; a < 3; ++a)
      b0[a] = (tlo[a] - lo_[a]) / bucket_size_, b1[a] = (thi[a] - lo_[a]) / bucket_size_;
    for (int64_t z = b0[2]; z <= b1[2]; ++z)
      for (int64_t y = b0[1]; y <= b1[1]; ++y)
        for (int64_t x = b0[0]; x <= b1[0]; ++x) f(static_cast<uint32_t>((z * dims_[1] + y) * dims_[0] + x));
  };
  buckets_ = build_csr(buckets, [&](auto&& emit) {
    for (uint32_t k = 0; k < tets_.size(); ++k) for_each_bucket(boxes_[k], [&](uint32_t b) { emit(b, k); });
  });
}

// Neighbouring tetrahedra are stored near each other, so that a query, which
// scans a bucket's tetrahedra, and the next query, which falls near it, touch
// few cache lines: the order is that of the buckets of the boxes' centres
// along a Morton (Z-order) curve. The verdicts do not depend on it.
void ReferenceSolid::sort_along_morton_curve() {
  auto spread = [](uint64_t x) {  // the bits of a 21-bit x, two zeros between each
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffff;
    x = (x | x << 16) & 0x1f0000ff0000ff;
    x = (x | x << 8) & 0x100f00f00f00f00f;
    x = (x | x << 4) & 0x10c30c30c30c30c3;
    x = (x | x << 2) & 0x1249249249249249;
    return x;
  };
  std::vector<std::pair<uint64_t, uint32_t>> order(tets_.size());
  for (uint32_t k = 0; k < tets_.size(); ++k) {
    uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const auto cell = static_cast<uint64_t>((boxes_[k][0][a] + boxes_[k][1][a]) / 2 - lo_[a]) /
                        static_cast<uint64_t>(bucket_size_);
      code |= spread(cell) << a;
    }
    order[k] = {code, k};
  }
  std::sort(order.begin(), order.end());
  std::vector<std::array<Point4, 4>> tets(tets_.size());
  std::vector<std::array<Point4, 2>> boxes(boxes_.size());
  for (size_t i = 0; i < order.size(); ++i) {
    tets[i] = tets_[order[i].second];
    boxes[i] = boxes_[order[i].second];
  }
  tets_ = std::move(tets);
  boxes_ = std::move(boxes);
}

size_t ReferenceSolid::bucket_of(const P4& p) const {
  std::array<int64_t, 3> b;
  for (int a = 0; a < 3; ++a) b[a] = (p[a] - lo_[a]) / bucket_size_;
  return static_cast<size_t>((b[2] * dims_[1] + b[1]) * dims_[0] + b[0]);
}

bool ReferenceSolid::contains4(const P4& p) const {
  if (tets_.empty()) return false;
  for (int a = 0; a < 3; ++a)
    if (p[a] < lo_[a] || p[a] > hi_[a]) return false;
  const size_t b = bucket_of(p);
  for (uint32_t k : buckets_.row(b)) {
    const auto& box = boxes_[k];
    if (p[0] < box[0][0] || p[0] > box[1][0] || p[1] < box[0][1] || p[1] > box[1][1] || p[2] < box[0][2] ||
        p[2] > box[1][2])
      continue;
    const auto& t = tets_[k];
    // Inside or on the boundary: p is on the inner side of every face.
    const auto orient = small_ ? orientation64 : orientation;
    if (orient(p, t[1], t[2], t[3]) >= 0 && orient(t[0], p, t[2], t[3]) >= 0 &&
        orient(t[0], t[1], p, t[3]) >= 0 && orient(t[0], t[1], t[2], p) >= 0)
      return true;
  }
  return false;
}

std::vector<uint8_t> ReferenceSolid::verdicts(const TetMesh& dt, std::span<const GridPoint> points) const {
  std::vector<uint8_t> out(dt.cells.size());
  for (size_t c = 0; c < out.size(); ++c) {
    const auto& k = dt.cells[c];
    out[c] = contains_centroid(points[k[0]], points[k[1]], points[k[2]], points[k[3]]);
  }
  return out;
}

bool ReferenceSolid::contains_centroid(const GridPoint& a, const GridPoint& b, const GridPoint& c,
                                       const GridPoint& d) const {
  return contains4(
      {int64_t{a.x} + b.x + c.x + d.x, int64_t{a.y} + b.y + c.y + d.y, int64_t{a.z} + b.z + c.z + d.z});
}

}  // namespace dtm
