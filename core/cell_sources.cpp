#include "core/cell_sources.h"

#include <algorithm>
#include <limits>

#include "common/csr.h"
#include "common/parallel_for.h"
#include "mesh/geometry.h"

namespace dtm {
namespace {

using Tet = std::array<uint32_t, 4>;

Tet sorted(Tet t) {
  std::sort(t.begin(), t.end());
  return t;
}

using P4 = std::array<int64_t, 3>;  // four times a grid point

P4 times4(const GridPoint& p) { return {4 * int64_t{p.x}, 4 * int64_t{p.y}, 4 * int64_t{p.z}}; }

// The sign of det(b - a, c - a, d - a), exactly.
int orientation(const P4& a, const P4& b, const P4& c, const P4& d) {
  const Int128 ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const Int128 vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const Int128 wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
  const Int128 det = ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx);
  return (det > 0) - (det < 0);
}

// Whether p lies in the closed tetrahedron t (of either orientation).
bool holds(const std::array<P4, 4>& t, const P4& p) {
  const int o = orientation(t[0], t[1], t[2], t[3]);
  if (o == 0) return false;
  return orientation(p, t[1], t[2], t[3]) * o >= 0 && orientation(t[0], p, t[2], t[3]) * o >= 0 &&
         orientation(t[0], t[1], p, t[3]) * o >= 0 && orientation(t[0], t[1], t[2], p) * o >= 0;
}

}  // namespace

CellSourceIndex::CellSourceIndex(std::span<const GridPoint> points, std::span<const Tet> reference)
    : points_(points), reference_(reference) {
  incident_ = build_csr(points.size(), [&](auto&& emit) {
    for (uint32_t t = 0; t < reference.size(); ++t)
      for (uint32_t v : reference[t]) emit(v, t);
  });
}

uint32_t CellSourceIndex::source(const Tet& cell, Found& found) const {
  // An input tetrahedron itself: among those at its first corner.
  const Tet corners = sorted(cell);
  for (uint32_t t : incident_.row(cell[0]))
    if (sorted(reference_[t]) == corners) {
      found = Found::kExact;
      return t;
    }
  // Else the first of its corners' tetrahedra holding its centroid, or the
  // one whose centroid is nearest.
  const P4 centre4 = {
      int64_t{points_[cell[0]].x} + points_[cell[1]].x + points_[cell[2]].x + points_[cell[3]].x,
      int64_t{points_[cell[0]].y} + points_[cell[1]].y + points_[cell[2]].y + points_[cell[3]].y,
      int64_t{points_[cell[0]].z} + points_[cell[1]].z + points_[cell[2]].z + points_[cell[3]].z};
  uint32_t best = 0;
  Int128 best_d2 = std::numeric_limits<Int128>::max();
  for (uint32_t v : cell)
    for (uint32_t t : incident_.row(v)) {
      std::array<P4, 4> at;
      P4 sum = {0, 0, 0};
      for (size_t i = 0; i < 4; ++i) {
        const GridPoint& p = points_[reference_[t][i]];
        at[i] = times4(p);
        sum[0] += p.x, sum[1] += p.y, sum[2] += p.z;
      }
      if (holds(at, centre4)) {
        found = Found::kHolding;
        return t;
      }
      Int128 d2 = 0;
      for (int a = 0; a < 3; ++a) {
        const Int128 d = sum[a] - centre4[a];
        d2 += d * d;
      }
      if (d2 < best_d2) best_d2 = d2, best = t;
    }
  found = Found::kNearest;
  return best;
}

CellSources cell_sources(std::span<const GridPoint> points, std::span<const Tet> reference,
                         std::span<const Tet> cells) {
  CellSources out;
  out.tetrahedron.assign(cells.size(), 0);
  const CellSourceIndex index(points, reference);
  std::vector<CellSourceIndex::Found> found(cells.size());
  parallel_for(
      cells.size(), [&](size_t c) { out.tetrahedron[c] = index.source(cells[c], found[c]); }, 1024);
  for (const CellSourceIndex::Found f : found) {
    out.exact += f == CellSourceIndex::Found::kExact;
    out.nearest += f == CellSourceIndex::Found::kNearest;
  }
  return out;
}

}  // namespace dtm
