#include "core/refill.h"

#include <algorithm>
#include <cmath>

#include "mesh/carving.h"
#include "mesh/delaunay.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

using Face = std::array<uint32_t, 3>;

Face sorted_face(Face f) {
  std::sort(f.begin(), f.end());
  return f;
}

// The three vertices of cell face i (opposite vertex i).
Face face_of(const std::array<uint32_t, 4>& c, int i) {
  static constexpr int kFace[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
  return {c[kFace[i][0]], c[kFace[i][1]], c[kFace[i][2]]};
}

}  // namespace

Refill refill_of(const LevelGeometry& L, uint32_t v, const ReferenceSolid* solid) {
  Refill r;
  std::vector<GridPoint> link;
  std::vector<uint32_t> ids;
  for (uint32_t u : L.neighbors.row(v)) {
    link.push_back(L.points[u]);
    ids.push_back(u);
  }
  const CavityFill fill = cavity_fill(link, ids, L.points[v]);
  if (fill.cells.empty()) return r;
  r.cells = fill.cells;
  r.kept.resize(r.cells.size());
  for (size_t c = 0; c < r.cells.size(); ++c) {
    const auto& k = r.cells[c];
    r.kept[c] = solid
                    ? solid->contains_centroid(L.points[k[0]], L.points[k[1]], L.points[k[2]], L.points[k[3]])
                    : kept_by_alpha(L.points, k, L.alpha);
  }
  // What lies across the cavity's border: the cell outside each face of the
  // star opposite v (the hull, when there is none), and whether it is kept.
  // (A sorted vector: a star has a few dozen faces, and this runs for every
  // candidate of every pass.)
  std::vector<std::pair<Face, bool>> outside_kept;
  for (uint32_t c : L.cells_of_vertex.row(v)) {
    const auto& cell = L.dt.cells[c];
    const int i = static_cast<int>(std::find(cell.begin(), cell.end(), v) - cell.begin());
    const int32_t across = L.dt.neighbors[c][i];
    outside_kept.emplace_back(sorted_face(face_of(cell, i)),
                              across >= 0 && L.in_mesh[static_cast<size_t>(across)]);
  }
  std::sort(outside_kept.begin(), outside_kept.end());
  for (size_t c = 0; c < r.cells.size(); ++c) {
    for (int i = 0; i < 4; ++i) {
      const int32_t n = fill.neighbors[c][i];
      if (n >= 0) {
        // An inner face, seen from its kept side.
        if (r.kept[c] && !r.kept[static_cast<size_t>(n)]) r.surface.push_back(face_of(r.cells[c], i));
        continue;
      }
      const Face key = sorted_face(face_of(r.cells[c], i));
      const auto it = std::lower_bound(outside_kept.begin(), outside_kept.end(), key,
                                       [](const auto& entry, const Face& f) { return entry.first < f; });
      const bool on_border = it != outside_kept.end() && it->first == key;
      const bool outside = on_border && it->second;  // the hull counts as removed
      if (r.kept[c] != outside) r.surface.push_back(face_of(r.cells[c], i));
    }
  }
  for (const auto& [face, kept] : outside_kept) r.border.push_back(face);  // sorted
  return r;
}

bool shape_allows(const LevelGeometry& L, const LevelSurface& surface, uint32_t v, const Refill& refill,
                  std::span<const GridPoint> at_risk, const FixedSurface& reference, double dmax) {
  if (refill.cells.empty()) return false;
  if (!L.boundary[v]) return std::all_of(refill.kept.begin(), refill.kept.end(), [](uint8_t k) { return k; });
  const double dmax2 = dmax * dmax;
  for (const Face& f : refill.surface) {
    for (uint32_t u : f)
      if (!L.boundary[u] && reference.squared_distance(L.points[u]) > dmax2) return false;
    const auto round3 = [&](int32_t a, int32_t b, int32_t c) {
      return static_cast<int32_t>(std::lround((double{1} * a + b + c) / 3));
    };
    const GridPoint &a = L.points[f[0]], &b = L.points[f[1]], &c = L.points[f[2]];
    if (reference.squared_distance({round3(a.x, b.x, c.x), round3(a.y, b.y, c.y), round3(a.z, b.z, c.z)}) >
        dmax2)
      return false;
  }
  std::vector<Face> after = refill.surface;
  for (uint32_t u : L.neighbors.row(v))
    for (uint32_t i : surface.around.row(u)) {
      const Face& t = surface.triangles[i];
      if (t[0] != v && t[1] != v && t[2] != v &&
          !std::binary_search(refill.border.begin(), refill.border.end(), sorted_face(t)))
        after.push_back(t);
    }
  auto near_surface = [&](const Vec3& p) {
    for (const Face& f : after)
      if (point_triangle_distance(p, to_vec(L.points[f[0]]), to_vec(L.points[f[1]]),
                                  to_vec(L.points[f[2]])) <= dmax)
        return true;
    return false;
  };
  if (!near_surface(to_vec(L.points[v]))) return false;
  for (const GridPoint& p : at_risk)
    if (!near_surface(to_vec(p))) return false;
  return true;
}

std::vector<Face> triangles_at_stake(const LevelSurface& surface, const LevelGeometry& L, uint32_t v,
                                     const Refill& refill) {
  std::vector<Face> out;
  for (uint32_t i : surface.around.row(v)) out.push_back(surface.triangles[i]);
  for (uint32_t u : L.neighbors.row(v))
    for (uint32_t i : surface.around.row(u)) {
      const Face& t = surface.triangles[i];
      // Each border triangle is around three neighbours: taken once, from its smallest vertex.
      if (u == std::min({t[0], t[1], t[2]}) &&
          std::binary_search(refill.border.begin(), refill.border.end(), sorted_face(t)))
        out.push_back(t);
    }
  return out;
}

// Ericson, Real-Time Collision Detection, §5.1.5: the closest point by
// Voronoi regions of the triangle.
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return norm(ap);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm(p - (a + ab * (d1 / (d1 - d3))));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm(p - (a + ac * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return norm(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = 1 / (va + vb + vc);
  return norm(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

}  // namespace dtm
