#include "core/cell_sources.h"

#include <algorithm>
#include <limits>
#include <unordered_map>

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

struct TetHash {
  size_t operator()(const Tet& t) const {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (uint32_t v : t) h = (h ^ v) * 0xBF58476D1CE4E5B9ull;
    return static_cast<size_t>(h ^ (h >> 31));
  }
};

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

CellSources cell_sources(std::span<const GridPoint> points, std::span<const Tet> reference,
                         std::span<const Tet> cells) {
  CellSources out;
  out.tetrahedron.assign(cells.size(), 0);
  std::unordered_map<Tet, uint32_t, TetHash> by_corners;
  by_corners.reserve(reference.size());
  for (uint32_t t = 0; t < reference.size(); ++t) by_corners.emplace(sorted(reference[t]), t);
  std::vector<uint32_t> others;
  for (uint32_t c = 0; c < cells.size(); ++c) {
    const auto it = by_corners.find(sorted(cells[c]));
    if (it != by_corners.end())
      out.tetrahedron[c] = it->second;
    else
      others.push_back(c);
  }
  out.exact = cells.size() - others.size();
  if (others.empty()) return out;
  const Csr incident = build_csr(points.size(), [&](auto&& emit) {
    for (uint32_t t = 0; t < reference.size(); ++t)
      for (uint32_t v : reference[t]) emit(v, t);
  });
  std::vector<uint8_t> by_nearest(others.size(), 0);
  parallel_for(
      others.size(),
      [&](size_t k) {
        const Tet& cell = cells[others[k]];
        const P4 centre4 = {
            int64_t{points[cell[0]].x} + points[cell[1]].x + points[cell[2]].x + points[cell[3]].x,
            int64_t{points[cell[0]].y} + points[cell[1]].y + points[cell[2]].y + points[cell[3]].y,
            int64_t{points[cell[0]].z} + points[cell[1]].z + points[cell[2]].z + points[cell[3]].z};
        uint32_t best = 0;
        Int128 best_d2 = std::numeric_limits<Int128>::max();
        for (uint32_t v : cell)
          for (uint32_t t : incident.row(v)) {
            std::array<P4, 4> corners;
            P4 sum = {0, 0, 0};
            for (size_t i = 0; i < 4; ++i) {
              const GridPoint& p = points[reference[t][i]];
              corners[i] = times4(p);
              sum[0] += p.x, sum[1] += p.y, sum[2] += p.z;
            }
            if (holds(corners, centre4)) {
              out.tetrahedron[others[k]] = t;
              return;
            }
            Int128 d2 = 0;
            for (int a = 0; a < 3; ++a) {
              const Int128 d = sum[a] - centre4[a];
              d2 += d * d;
            }
            if (d2 < best_d2) best_d2 = d2, best = t;
          }
        out.tetrahedron[others[k]] = best;
        by_nearest[k] = 1;
      },
      256);
  out.nearest = static_cast<uint64_t>(std::count(by_nearest.begin(), by_nearest.end(), uint8_t{1}));
  return out;
}

}  // namespace dtm
