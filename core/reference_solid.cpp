#include "core/reference_solid.h"

#include <algorithm>
#include <cmath>

#include "common/parallel_for.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"

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

P4 times4(const GridPoint& p) { return {4 * int64_t{p.x}, 4 * int64_t{p.y}, 4 * int64_t{p.z}}; }

}  // namespace

ReferenceSolid::ReferenceSolid(std::span<const GridPoint> points,
                               std::span<const std::array<uint32_t, 4>> cells,
                               std::span<const std::array<uint32_t, 3>> boundary)
    : points_(points), cells_(cells) {
  build(boundary);
}

ReferenceSolid::ReferenceSolid(std::span<const GridPoint> points,
                               std::span<const std::array<uint32_t, 4>> cells)
    : points_(points), cells_(cells) {
  build(boundary_triangles(cells));
}

void ReferenceSolid::build(std::span<const std::array<uint32_t, 3>> boundary) {
  const size_t n = cells_.size();
  orientation_.resize(n);
  bool any = false;
  for (size_t k = 0; k < n; ++k) {
    const auto& t = cells_[k];
    for (uint32_t v : t) {
      const P4 p = times4(points_[v]);
      for (int a = 0; a < 3; ++a) {
        lo_[a] = any ? std::min(lo_[a], p[a]) : p[a];
        hi_[a] = any ? std::max(hi_[a], p[a]) : p[a];
      }
      any = true;
    }
  }
  small_ = std::max({std::abs(lo_[0]), std::abs(lo_[1]), std::abs(lo_[2]), std::abs(hi_[0]), std::abs(hi_[1]),
                     std::abs(hi_[2])}) < (int64_t{1} << 18);
  parallel_for(
      n,
      [&](size_t k) {
        const auto& t = cells_[k];
        const P4 a = times4(points_[t[0]]), b = times4(points_[t[1]]), c = times4(points_[t[2]]),
                 d = times4(points_[t[3]]);
        const int o = small_ ? orientation_in<int64_t>(a, b, c, d) : orientation_in<Int128>(a, b, c, d);
        orientation_[k] = o > 0 ? 1 : o < 0 ? 2 : 0;
      },
      4096);
  if (!any) {
    state_.assign(1, kOutside);
    return;
  }
  // About two grid cells per tetrahedron, at most 2^26 (256 MiB of states).
  const double volume = static_cast<double>(hi_[0] - lo_[0] + 1) * static_cast<double>(hi_[1] - lo_[1] + 1) *
                        static_cast<double>(hi_[2] - lo_[2] + 1);
  const double target = std::clamp(2.0 * static_cast<double>(n), 4096.0, 67108864.0);
  step_ = std::max<int64_t>(2, static_cast<int64_t>(std::ceil(std::cbrt(volume / target))));
  step_ += step_ & 1;
  for (int a = 0; a < 3; ++a) dims_[a] = (hi_[a] - lo_[a]) / step_ + 1;
  const size_t total = static_cast<size_t>(dims_[0] * dims_[1] * dims_[2]);
  const uint32_t kUnknown = UINT32_MAX, kMixed = UINT32_MAX - 1;
  state_.assign(total, kUnknown);

  // The grid cells a closed box [bl, bh] meets: those whose closed extent
  // overlaps it (a box on a cell's face meets both cells).
  auto range = [&](const P4& bl, const P4& bh, std::array<int64_t, 3>& c0, std::array<int64_t, 3>& c1) {
    for (int a = 0; a < 3; ++a) {
      const int64_t l = bl[a] - lo_[a], h = bh[a] - lo_[a];
      c0[a] = std::max<int64_t>(0, l % step_ == 0 ? l / step_ - 1 : l / step_);
      c1[a] = std::min(dims_[a] - 1, h / step_);
    }
  };
  auto box_of = [&](std::span<const uint32_t> corners, P4& bl, P4& bh) {
    bl = bh = times4(points_[corners[0]]);
    for (uint32_t v : corners.subspan(1)) {
      const P4 p = times4(points_[v]);
      for (int a = 0; a < 3; ++a) bl[a] = std::min(bl[a], p[a]), bh[a] = std::max(bh[a], p[a]);
    }
  };
  auto for_each_cell = [&](const std::array<int64_t, 3>& c0, const std::array<int64_t, 3>& c1, auto&& f) {
    for (int64_t z = c0[2]; z <= c1[2]; ++z)
      for (int64_t y = c0[1]; y <= c1[1]; ++y)
        for (int64_t x = c0[0]; x <= c1[0]; ++x) f(static_cast<size_t>((z * dims_[1] + y) * dims_[0] + x));
  };
  for (const auto& t : boundary) {
    P4 bl, bh;
    box_of(t, bl, bh);
    std::array<int64_t, 3> c0, c1;
    range(bl, bh, c0, c1);
    for_each_cell(c0, c1, [&](size_t cell) { state_[cell] = kMixed; });
  }

  // Mixed cells get their rows, then the tetrahedra whose boxes meet them:
  // first, on every core, which tetrahedra meet a mixed cell at all (those
  // near the boundary), then the rows.
  uint32_t mixed = 0;
  for (uint32_t& s : state_)
    if (s == kMixed) s = kFirstMixed + mixed++;
  std::vector<uint8_t> near(n, 0);
  parallel_for((n + 4095) / 4096,
               [&](size_t block) {
                 for (size_t k = block * 4096; k < std::min(n, block * 4096 + 4096); ++k) {
                   if (orientation_[k] == 0) continue;
                   P4 bl, bh;
                   box_of(cells_[k], bl, bh);
                   std::array<int64_t, 3> c0, c1;
                   range(bl, bh, c0, c1);
                   bool any = false;
                   for_each_cell(c0, c1, [&](size_t cell) { any = any || state_[cell] != kUnknown; });
                   near[k] = any;
                 }
               },
               2);
  mixed_ = build_csr(mixed, [&](auto&& emit) {
    for (uint32_t k = 0; k < cells_.size(); ++k) {
      if (!near[k]) continue;
      P4 bl, bh;
      box_of(cells_[k], bl, bh);
      std::array<int64_t, 3> c0, c1;
      range(bl, bh, c0, c1);
      for_each_cell(c0, c1, [&](size_t cell) {
        if (state_[cell] >= kFirstMixed && state_[cell] != kUnknown) emit(state_[cell] - kFirstMixed, k);
      });
    }
  });

  // The groups of untouched cells, by flood fill through faces. A group
  // lies wholly inside or outside; it is classified by one exact test of the
  // centre of a face it shares with a mixed cell: that point is in the
  // group's closed cells (so not on the boundary), and every tetrahedron
  // holding it meets the mixed cell's closure (so is on its list). A group
  // with no mixed neighbour is the whole grid, which the boundary does not
  // touch: outside.
  const int64_t steps[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  std::vector<uint32_t> queue;
  for (size_t start = 0; start < total; ++start) {
    if (state_[start] != kUnknown) continue;
    // The group, marked kGrouping while it is gathered.
    constexpr uint32_t kGrouping = UINT32_MAX - 2;
    std::vector<uint32_t> group;
    state_[start] = kGrouping;
    queue.assign(1, static_cast<uint32_t>(start));
    uint32_t verdict = kOutside;
    bool decided = false;
    while (!queue.empty()) {
      const uint32_t cell = queue.back();
      queue.pop_back();
      group.push_back(cell);
      const int64_t x = int64_t{cell} % dims_[0], y = int64_t{cell} / dims_[0] % dims_[1],
                    z = int64_t{cell} / (dims_[0] * dims_[1]);
      for (const auto& st : steps) {
        const int64_t nx = x + st[0], ny = y + st[1], nz = z + st[2];
        if (nx < 0 || ny < 0 || nz < 0 || nx >= dims_[0] || ny >= dims_[1] || nz >= dims_[2]) continue;
        const size_t nb = static_cast<size_t>((nz * dims_[1] + ny) * dims_[0] + nx);
        if (state_[nb] == kUnknown) {
          state_[nb] = kGrouping;
          queue.push_back(static_cast<uint32_t>(nb));
        } else if (!decided && state_[nb] >= kFirstMixed && state_[nb] < kGrouping) {
          // The centre of the face between cell and nb (integral: step_ is even).
          P4 centre = {lo_[0] + x * step_ + step_ / 2, lo_[1] + y * step_ + step_ / 2,
                       lo_[2] + z * step_ + step_ / 2};
          for (int a = 0; a < 3; ++a)
            if (st[a] != 0) centre[a] += st[a] * step_ / 2;
          bool inside = false;
          for (uint32_t k : mixed_.row(state_[nb] - kFirstMixed))
            inside = inside || in_tetrahedron(centre, k);
          verdict = inside ? kInside : kOutside;
          decided = true;
        }
      }
    }
    for (uint32_t cell : group) state_[cell] = verdict;
  }
}

bool ReferenceSolid::in_tetrahedron(const P4& p, uint32_t k) const {
  if (orientation_[k] == 0) return false;
  const auto& t = cells_[k];
  P4 c[4] = {times4(points_[t[0]]), times4(points_[t[1]]), times4(points_[t[2]]), times4(points_[t[3]])};
  for (int a = 0; a < 3; ++a) {
    const int64_t l = std::min({c[0][a], c[1][a], c[2][a], c[3][a]}),
                  h = std::max({c[0][a], c[1][a], c[2][a], c[3][a]});
    if (p[a] < l || p[a] > h) return false;
  }
  if (orientation_[k] == 2) std::swap(c[2], c[3]);
  // Inside or on the boundary: p is on the inner side of every face.
  const auto orient = small_ ? orientation_in<int64_t> : orientation_in<Int128>;
  return orient(p, c[1], c[2], c[3]) >= 0 && orient(c[0], p, c[2], c[3]) >= 0 &&
         orient(c[0], c[1], p, c[3]) >= 0 && orient(c[0], c[1], c[2], p) >= 0;
}

size_t ReferenceSolid::cell_of(const P4& p) const {
  std::array<int64_t, 3> c;
  for (int a = 0; a < 3; ++a) c[a] = (p[a] - lo_[a]) / step_;
  return static_cast<size_t>((c[2] * dims_[1] + c[1]) * dims_[0] + c[0]);
}

bool ReferenceSolid::contains4(const P4& p) const {
  if (cells_.empty()) return false;
  for (int a = 0; a < 3; ++a)
    if (p[a] < lo_[a] || p[a] > hi_[a]) return false;
  const uint32_t s = state_[cell_of(p)];
  if (s < kFirstMixed) return s == kInside;
  for (uint32_t k : mixed_.row(s - kFirstMixed))
    if (in_tetrahedron(p, k)) return true;
  return false;
}

ReferenceSolid::Layout ReferenceSolid::layout() const { return {dims_, mixed_.rows(), mixed_.items.size()}; }

}  // namespace dtm
