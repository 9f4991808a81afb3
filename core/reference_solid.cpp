#include "core/reference_solid.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "common/atomic_counts.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/release.h"
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

// The plane through a, b, c as n . p = offset, n = (b - a) x (c - a),
// exact: with coordinates under 2^18 (x4) the normal's components are under
// 2^39 and n . p under 2^59, which 64 bits hold; beyond, 128.
template <class Int>
struct Plane {
  Int n[3], offset;
  Plane(const P4& a, const P4& b, const P4& c) {
    const Int ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const Int vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    n[0] = uy * vz - uz * vy, n[1] = uz * vx - ux * vz, n[2] = ux * vy - uy * vx;
    offset = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
  }
  Int at(const P4& p) const { return n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - offset; }
  // The least and greatest of n . p - offset over the closed box [lo, hi].
  std::pair<Int, Int> range(const P4& lo, const P4& hi) const {
    Int least = -offset, most = -offset;
    for (int a = 0; a < 3; ++a) {
      const Int l = n[a] * lo[a], h = n[a] * hi[a];
      least += std::min(l, h), most += std::max(l, h);
    }
    return {least, most};
  }
};

// Whether the closed triangle (a, b, c) may meet the closed box [lo, hi]:
// false only when the box lies strictly on one side of its plane (its
// bounding box is tested by the caller). A flat triangle may meet anything.
template <class Int>
bool plane_meets_box(const P4& a, const P4& b, const P4& c, const P4& lo, const P4& hi) {
  const Plane<Int> plane(a, b, c);
  const auto [least, most] = plane.range(lo, hi);
  return least <= 0 && most >= 0;
}

// Whether the closed tetrahedron t (corners in either orientation) may meet
// the closed box [lo, hi]: false only when the box lies strictly outside
// one of its faces' planes (its bounding box is tested by the caller).
template <class Int>
bool tetrahedron_meets_box(const std::array<P4, 4>& t, const P4& lo, const P4& hi) {
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  for (int f = 0; f < 4; ++f) {
    const Plane<Int> plane(t[kFace[f][0]], t[kFace[f][1]], t[kFace[f][2]]);
    const Int inner = plane.at(t[f]);  // the side the tetrahedron is on
    if (inner == 0) return true;       // flat
    const auto [least, most] = plane.range(lo, hi);
    if ((inner > 0 && most < 0) || (inner < 0 && least > 0)) return false;
  }
  return true;
}

}  // namespace

ReferenceSolid::ReferenceSolid(std::span<const GridPoint> points,
                               std::span<const std::array<uint32_t, 4>> cells,
                               std::span<const std::array<uint32_t, 3>> boundary)
    : points_(points) {
  build(cells, boundary, Extent::of(points, cells, cells.size()));
  keep_listed(cells);
}

ReferenceSolid::ReferenceSolid(std::span<const GridPoint> points,
                               std::span<const std::array<uint32_t, 4>> cells)
    : ReferenceSolid(points, cells, boundary_triangles(cells)) {}

ReferenceSolid::ReferenceSolid(std::span<const GridPoint> points,
                               std::span<const std::array<uint32_t, 4>> held,
                               const std::function<bool(const std::array<uint32_t, 4>&)>& owns,
                               std::span<const std::array<uint32_t, 3>> boundary, const Extent& whole,
                               RankExchange& exchange)
    : points_(points), part_(true) {
  build(held, boundary, whole, &exchange);
  mark_complete(held, owns, exchange);
  keep_listed(held);
}

void ReferenceSolid::mark_complete(std::span<const std::array<uint32_t, 4>> cells,
                                   const std::function<bool(const std::array<uint32_t, 4>&)>& owns,
                                   RankExchange& exchange) {
  // A mixed cell's list here is complete when it is as long as the lists of
  // the cells each rank owns, added up over the ranks: summed a slice of
  // rows at a time (4 bytes a row and rank).
  const size_t rows = mixed_.rows();
  complete_.assign((rows + 63) / 64, 0);
  constexpr size_t kSlice = size_t{1} << 20;
  for (size_t first = 0;; first += kSlice) {
    const size_t count = first < rows ? std::min(kSlice, rows - first) : 0;
    std::vector<uint32_t> own(count, 0);
    parallel_for(
        count,
        [&](size_t i) {
          for (uint32_t k : mixed_.row(first + i)) own[i] += owns(cells[k]) ? 1 : 0;
        },
        4096);
    std::vector<uint8_t> bytes(count * 4);
    for (size_t i = 0; i < count; ++i)
      for (int b = 0; b < 4; ++b) bytes[4 * i + b] = static_cast<uint8_t>(own[i] >> (8 * b));
    release(own);
    // Every rank has the same rows: each slice is one exchange on all.
    const std::vector<std::vector<uint8_t>> all = exchange.all_gather(bytes);
    for (size_t i = 0; i < count; ++i) {
      uint64_t total = 0;
      for (const auto& r : all)
        for (int b = 0; b < 4; ++b) total += uint64_t{r[4 * i + b]} << (8 * b);
      const size_t row = first + i;
      if (mixed_.row(row).size() == total) complete_[row / 64] |= uint64_t{1} << (row % 64);
    }
    if (first + count >= rows) break;
  }
}

void ReferenceSolid::keep_listed(std::span<const std::array<uint32_t, 4>> cells) {
  std::vector<uint32_t> listed(mixed_.items.begin(), mixed_.items.end());
  parallel_sort(listed.begin(), listed.end());
  listed.erase(std::unique(listed.begin(), listed.end()), listed.end());
  kept_.resize(listed.size());
  std::vector<uint8_t> orientation(listed.size());
  for (size_t i = 0; i < listed.size(); ++i)
    kept_[i] = cells[listed[i]], orientation[i] = orientation_[listed[i]];
  parallel_for(
      mixed_.items.size(),
      [&](size_t i) {
        mixed_.items[i] = static_cast<uint32_t>(
            std::lower_bound(listed.begin(), listed.end(), mixed_.items[i]) - listed.begin());
      },
      4096);
  orientation_ = std::move(orientation);
}

ReferenceSolid::Extent ReferenceSolid::Extent::of(std::span<const GridPoint> points,
                                                  std::span<const std::array<uint32_t, 4>> cells,
                                                  uint64_t owned) {
  Extent e;
  e.tetrahedra = owned;
  for (const auto& t : cells)
    for (uint32_t v : t) {
      const P4 p = times4(points[v]);
      for (int a = 0; a < 3; ++a) {
        e.lo[a] = e.any ? std::min(e.lo[a], p[a]) : p[a];
        e.hi[a] = e.any ? std::max(e.hi[a], p[a]) : p[a];
      }
      e.any = true;
    }
  return e;
}

void ReferenceSolid::Extent::add(const Extent& o) {
  tetrahedra += o.tetrahedra;
  if (!o.any) return;
  for (int a = 0; a < 3; ++a) {
    lo[a] = any ? std::min(lo[a], o.lo[a]) : o.lo[a];
    hi[a] = any ? std::max(hi[a], o.hi[a]) : o.hi[a];
  }
  any = true;
}

std::vector<std::array<uint32_t, 4>> ReferenceSolid::near_boundary(
    std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells,
    std::span<const std::array<uint32_t, 3>> boundary, const Extent& whole,
    const std::function<bool(const std::array<uint32_t, 4>&)>& mine) {
  ReferenceSolid s(points);
  if (!s.frame(whole)) return {};
  s.orient(cells);
  s.mark_mixed(boundary);
  std::vector<std::array<uint32_t, 4>> near;
  s.for_each_meeting(cells, &mine, [&](std::span<const std::pair<uint32_t, uint32_t>> block) {
    for (size_t i = 0; i < block.size(); ++i)
      if (i == 0 || block[i].second != block[i - 1].second) near.push_back(cells[block[i].second]);
  });
  return near;
}

namespace {

// Sets bits [first, last) of `words`, on one of several threads that set
// disjoint ranges: a word wholly in the range is this thread's alone, the
// two at its ends may hold another's bits.
void set_bits(std::vector<uint64_t>& words, size_t first, size_t last) {
  while (first < last) {
    const size_t w = first / 64, lo = first % 64, hi = std::min<size_t>(64, lo + (last - first));
    const uint64_t mask = hi - lo == 64 ? ~uint64_t{0} : ((uint64_t{1} << (hi - lo)) - 1) << lo;
    if (mask == ~uint64_t{0})
      words[w] = mask;
    else
      atomic_fetch_or(words[w], mask);
    first += hi - lo;
  }
}

}  // namespace

bool ReferenceSolid::frame(const Extent& whole) {
  tetrahedra_ = whole.tetrahedra;
  if (!whole.any) {
    inside_.assign(1, 0);
    mixed_cells_.assign(1, 0);
    mixed_before_.assign(1, 0);
    return false;
  }
  lo_ = whole.lo, hi_ = whole.hi;
  small_ = std::max({std::abs(lo_[0]), std::abs(lo_[1]), std::abs(lo_[2]), std::abs(hi_[0]), std::abs(hi_[1]),
                     std::abs(hi_[2])}) < (int64_t{1} << 18);
  // About two grid cells per tetrahedron, at most 2^26 (a byte each while
  // building, two bits after).
  const double volume = static_cast<double>(hi_[0] - lo_[0] + 1) * static_cast<double>(hi_[1] - lo_[1] + 1) *
                        static_cast<double>(hi_[2] - lo_[2] + 1);
  const double target = std::clamp(2.0 * static_cast<double>(whole.tetrahedra), 4096.0, 67108864.0);
  step_ = std::max<int64_t>(2, static_cast<int64_t>(std::ceil(std::cbrt(volume / target))));
  step_ += step_ & 1;
  for (int a = 0; a < 3; ++a) dims_[a] = (hi_[a] - lo_[a]) / step_ + 1;
  return true;
}

void ReferenceSolid::orient(std::span<const std::array<uint32_t, 4>> cells) {
  orientation_.resize(cells.size());
  parallel_for(
      cells.size(),
      [&](size_t k) {
        const auto& t = cells[k];
        const P4 a = times4(points_[t[0]]), b = times4(points_[t[1]]), c = times4(points_[t[2]]),
                 d = times4(points_[t[3]]);
        const int o = small_ ? orientation_in<int64_t>(a, b, c, d) : orientation_in<Int128>(a, b, c, d);
        orientation_[k] = o > 0 ? 1 : o < 0 ? 2 : 0;
      },
      4096);
}

void ReferenceSolid::cell_range(const P4& bl, const P4& bh, std::array<int64_t, 3>& c0,
                                std::array<int64_t, 3>& c1) const {
  for (int a = 0; a < 3; ++a) {
    const int64_t l = bl[a] - lo_[a], h = bh[a] - lo_[a];
    c0[a] = std::max<int64_t>(0, l % step_ == 0 ? l / step_ - 1 : l / step_);
    c1[a] = std::min(dims_[a] - 1, h / step_);
  }
}

void ReferenceSolid::box_of(std::span<const uint32_t> corners, P4& bl, P4& bh) const {
  bl = bh = times4(points_[corners[0]]);
  for (uint32_t v : corners.subspan(1)) {
    const P4 p = times4(points_[v]);
    for (int a = 0; a < 3; ++a) bl[a] = std::min(bl[a], p[a]), bh[a] = std::max(bh[a], p[a]);
  }
}

template <class F>
void ReferenceSolid::for_each_cell_box(const std::array<int64_t, 3>& c0, const std::array<int64_t, 3>& c1,
                                       F&& f) const {
  for (int64_t z = c0[2]; z <= c1[2]; ++z)
    for (int64_t y = c0[1]; y <= c1[1]; ++y)
      for (int64_t x = c0[0]; x <= c1[0]; ++x) {
        const P4 bl = {lo_[0] + x * step_, lo_[1] + y * step_, lo_[2] + z * step_};
        const P4 bh = {bl[0] + step_, bl[1] + step_, bl[2] + step_};
        f(static_cast<size_t>((z * dims_[1] + y) * dims_[0] + x), bl, bh);
      }
}

void ReferenceSolid::mark_mixed(std::span<const std::array<uint32_t, 3>> boundary) {
  const size_t total = static_cast<size_t>(dims_[0] * dims_[1] * dims_[2]);
  // Which cells are mixed, one bit each (marked straight here: a byte per
  // cell while building took 64 MiB at bunny_10m's 2^26 cells, on every
  // rank); a few MiB that stay in cache while every tetrahedron's cells
  // are looked up (most are not mixed). Mixed: the cells a boundary
  // triangle meets (its box, then its plane).
  const size_t words = (total + 63) / 64;
  mixed_cells_.assign(words, 0);
  const auto mixed = [&](size_t cell) { return (mixed_cells_[cell / 64] >> (cell % 64)) & 1; };
  for (const auto& t : boundary) {
    P4 bl, bh;
    box_of(t, bl, bh);
    std::array<int64_t, 3> c0, c1;
    cell_range(bl, bh, c0, c1);
    const P4 a = times4(points_[t[0]]), b = times4(points_[t[1]]), c = times4(points_[t[2]]);
    for_each_cell_box(c0, c1, [&](size_t cell, const P4& cl, const P4& ch) {
      if (mixed(cell)) return;
      if (small_ ? plane_meets_box<int64_t>(a, b, c, cl, ch) : plane_meets_box<Int128>(a, b, c, cl, ch))
        mixed_cells_[cell / 64] |= uint64_t{1} << (cell % 64);
    });
  }
  mixed_before_.resize(words);
  uint32_t count = 0;
  for (size_t w = 0; w < words; ++w) {
    mixed_before_[w] = count;
    count += static_cast<uint32_t>(std::popcount(mixed_cells_[w]));
  }
}

void ReferenceSolid::for_each_meeting(
    std::span<const std::array<uint32_t, 4>> cells,
    const std::function<bool(const std::array<uint32_t, 4>&)>* mine,
    const std::function<void(std::span<const std::pair<uint32_t, uint32_t>>)>& take) const {
  // Found on every core in blocks of tetrahedra, each block's pairs in
  // tetrahedron order, and handed over in block order, a few blocks at a
  // time: all of them at once took 8 bytes a pair (bunny_10m: 0.4 GB).
  const size_t n = cells.size();
  constexpr size_t kTetBlock = 16384, kBlocksAtOnce = 64;
  const size_t blocks = (n + kTetBlock - 1) / kTetBlock;
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> pairs(std::min(blocks, kBlocksAtOnce));
  for (size_t first = 0; first < blocks; first += kBlocksAtOnce) {
    const size_t count = std::min(kBlocksAtOnce, blocks - first);
    parallel_for(
        count,
        [&](size_t b) {
          pairs[b].clear();
          const size_t block = first + b;
          std::array<P4, 4> corners;
          for (size_t k = block * kTetBlock; k < std::min(n, block * kTetBlock + kTetBlock); ++k) {
            if (orientation_[k] == 0 || (mine && !(*mine)(cells[k]))) continue;
            P4 bl, bh;
            box_of(cells[k], bl, bh);
            std::array<int64_t, 3> c0, c1;
            cell_range(bl, bh, c0, c1);
            bool corners_read = false;
            for_each_cell_box(c0, c1, [&](size_t cell, const P4& cl, const P4& ch) {
              if (!(mixed_cells_[cell / 64] >> (cell % 64) & 1)) return;
              if (!corners_read) {
                for (int i = 0; i < 4; ++i) corners[i] = times4(points_[cells[k][i]]);
                corners_read = true;
              }
              if (small_ ? tetrahedron_meets_box<int64_t>(corners, cl, ch)
                         : tetrahedron_meets_box<Int128>(corners, cl, ch))
                pairs[b].emplace_back(mixed_row(cell), static_cast<uint32_t>(k));
            });
          }
        },
        2);
    for (size_t b = 0; b < count; ++b) take(pairs[b]);
  }
}

void ReferenceSolid::build(std::span<const std::array<uint32_t, 4>> cells,
                           std::span<const std::array<uint32_t, 3>> boundary, const Extent& whole,
                           RankExchange* exchange) {
  if (!frame(whole)) return;
  orient(cells);
  mark_mixed(boundary);

  // Mixed cells list the tetrahedra that may meet them, counted out in
  // block order, so that every row lists its tetrahedra ascending (the
  // pairs found twice, to count and to fill, rather than held).
  const uint32_t mixed = mixed_before_.back() + static_cast<uint32_t>(std::popcount(mixed_cells_.back()));
  mixed_ = build_csr(mixed, [&](auto&& emit) {
    for_each_meeting(cells, nullptr, [&](std::span<const std::pair<uint32_t, uint32_t>> block) {
      for (const auto& [row, k] : block) emit(row, k);
    });
  });

  // The untouched cells, row by row along x (rows on every core): a run of
  // them between two mixed cells lies wholly inside or outside, classified
  // by one exact test of the centre of the face it shares with the mixed
  // cell before it: that point is in the run's closed cells (so not on the
  // boundary), and every tetrahedron holding it meets the mixed cell's
  // closure (so is on its list). A run that reaches the grid's end along x
  // is outside: the first cell holds points of the plane x = lo, which the
  // solid meets only on its boundary (which this cell does not), the last
  // points beyond hi.
  // Made in parts, a run is inside when any rank's cells hold that point:
  // each rank tests its own, and the runs' bits (the same runs on every
  // rank, numbered in row order) are OR-ed over the ranks.
  const size_t grid_rows = static_cast<size_t>(dims_[1] * dims_[2]);
  std::vector<uint32_t> first_run;  // per grid row, its first run's number (parts only)
  std::vector<uint8_t> found;       // per run
  const auto for_each_run = [&](size_t row, auto&& f) {
    const size_t row_start = row * static_cast<size_t>(dims_[0]);
    const auto mixed = [&](int64_t x) {
      const size_t cell = row_start + static_cast<size_t>(x);
      return (mixed_cells_[cell / 64] >> (cell % 64)) & 1;
    };
    for (int64_t x = 0; x < dims_[0];) {
      if (mixed(x)) {
        ++x;
        continue;
      }
      int64_t end = x;
      while (end < dims_[0] && !mixed(end)) ++end;
      f(x, end);
      x = end;
    }
  };
  const auto holds_centre = [&](size_t row, int64_t x) {
    if (x == 0) return false;
    const int64_t y = static_cast<int64_t>(row) % dims_[1], z = static_cast<int64_t>(row) / dims_[1];
    const P4 centre = {lo_[0] + x * step_, lo_[1] + y * step_ + step_ / 2, lo_[2] + z * step_ + step_ / 2};
    for (uint32_t k : mixed_.row(mixed_row(row * static_cast<size_t>(dims_[0]) + static_cast<size_t>(x) - 1)))
      if (in_tetrahedron(centre, cells[k], orientation_[k])) return true;
    return false;
  };
  if (exchange) {
    first_run.assign(grid_rows + 1, 0);
    parallel_for(
        grid_rows, [&](size_t row) { for_each_run(row, [&](int64_t, int64_t) { ++first_run[row + 1]; }); },
        64);
    for (size_t r = 0; r < grid_rows; ++r) first_run[r + 1] += first_run[r];
    found.assign(first_run.back(), 0);
    parallel_for(
        grid_rows,
        [&](size_t row) {
          uint32_t run = first_run[row];
          for_each_run(
              row, [&](int64_t x, int64_t end) { found[run++] = end < dims_[0] && holds_centre(row, x); });
        },
        64);
    std::vector<uint8_t> bits((found.size() + 7) / 8, 0);
    for (size_t i = 0; i < found.size(); ++i) bits[i / 8] |= static_cast<uint8_t>(found[i] << (i % 8));
    for (const auto& other : exchange->all_gather(bits))
      for (size_t i = 0; i < found.size(); ++i) found[i] |= (other[i / 8] >> (i % 8)) & 1;
  }
  // The inside runs' bits set on every core: rows that share a word set
  // theirs with an atomic OR.
  inside_.assign(mixed_cells_.size(), 0);
  parallel_for(
      grid_rows,
      [&](size_t row) {
        const size_t row_start = row * static_cast<size_t>(dims_[0]);
        uint32_t run = exchange ? first_run[row] : 0;
        for_each_run(row, [&](int64_t x, int64_t end) {
          const bool inside = exchange ? found[run++] != 0 : end < dims_[0] && holds_centre(row, x);
          if (inside)
            set_bits(inside_, row_start + static_cast<size_t>(x), row_start + static_cast<size_t>(end));
        });
      },
      64);
}

uint32_t ReferenceSolid::mixed_row(size_t cell) const {
  const uint64_t below = (uint64_t{1} << (cell % 64)) - 1;
  return mixed_before_[cell / 64] + static_cast<uint32_t>(std::popcount(mixed_cells_[cell / 64] & below));
}

bool ReferenceSolid::in_tetrahedron(const P4& p, const std::array<uint32_t, 4>& t,
                                    uint8_t orientation) const {
  if (orientation == 0) return false;
  P4 c[4] = {times4(points_[t[0]]), times4(points_[t[1]]), times4(points_[t[2]]), times4(points_[t[3]])};
  for (int a = 0; a < 3; ++a) {
    const int64_t l = std::min({c[0][a], c[1][a], c[2][a], c[3][a]}),
                  h = std::max({c[0][a], c[1][a], c[2][a], c[3][a]});
    if (p[a] < l || p[a] > h) return false;
  }
  if (orientation == 2) std::swap(c[2], c[3]);
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
  if (tetrahedra_ == 0) return false;
  for (int a = 0; a < 3; ++a)
    if (p[a] < lo_[a] || p[a] > hi_[a]) return false;
  const size_t cell = cell_of(p);
  if (!(mixed_cells_[cell / 64] >> (cell % 64) & 1)) return inside_[cell / 64] >> (cell % 64) & 1;
  for (uint32_t k : mixed_.row(mixed_row(cell)))
    if (in_tetrahedron(p, kept_[k], orientation_[k])) return true;
  return false;
}

ReferenceSolid::Answer ReferenceSolid::answer4(const P4& p) const {
  if (tetrahedra_ == 0) return Answer::kOutside;
  for (int a = 0; a < 3; ++a)
    if (p[a] < lo_[a] || p[a] > hi_[a]) return Answer::kOutside;
  const size_t cell = cell_of(p);
  if (!(mixed_cells_[cell / 64] >> (cell % 64) & 1))
    return inside_[cell / 64] >> (cell % 64) & 1 ? Answer::kInside : Answer::kOutside;
  const uint32_t row = mixed_row(cell);
  for (uint32_t k : mixed_.row(row))
    if (in_tetrahedron(p, kept_[k], orientation_[k])) return Answer::kInside;
  return !part_ || (complete_[row / 64] >> (row % 64) & 1) ? Answer::kOutside : Answer::kUnknown;
}

bool ReferenceSolid::holds4(const P4& p) const { return answer4(p) == Answer::kInside; }

ReferenceSolid::Layout ReferenceSolid::layout() const {
  return {dims_, mixed_.rows(), mixed_.items.size(), kept_.size()};
}

}  // namespace dtm
