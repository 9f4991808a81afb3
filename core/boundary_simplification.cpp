#include "core/boundary_simplification.h"

#include <cmath>
#include <unordered_map>

#include "common/parallel_for.h"
#include "mesh/geometry.h"

namespace dtm {
namespace {

struct Umbrella {
  Vec3 vector_area;
  Vec3 link_centroid;
  bool is_disk = false;
};

// `triangles`: the outward triangles of the umbrella of v.
Umbrella umbrella_of(uint32_t v, std::span<const std::array<uint32_t, 3>> triangles,
                     std::span<const GridPoint> points) {
  Umbrella u;
  // Each outward triangle (v, a, b) contributes the directed link edge a -> b;
  // the umbrella is a disk when these edges form one cycle through every
  // link vertex exactly once.
  std::unordered_map<uint32_t, uint32_t> next;
  next.reserve(triangles.size() * 2);
  const Vec3 pv = to_vec(points[v]);
  for (const auto& t : triangles) {
    int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    const uint32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
    if (!next.emplace(a, b).second) return u;  // a starts two link edges
    u.vector_area += cross(to_vec(points[a]) - pv, to_vec(points[b]) - pv) * 0.5;
  }
  uint32_t steps = 0, start = next.begin()->first, cur = start;
  do {
    auto it = next.find(cur);
    if (it == next.end()) return u;  // open link: v sits on a border of the surface
    cur = it->second;
    u.link_centroid += to_vec(points[cur]);
    ++steps;
  } while (cur != start && steps <= next.size());
  if (cur != start || steps != next.size()) return u;  // several cycles
  u.link_centroid = u.link_centroid * (1.0 / steps);
  u.is_disk = steps >= 3;
  return u;
}

}  // namespace

std::vector<BoundaryCandidate> boundary_candidates(const LevelGeometry& L, const Csr& represented,
                                                   std::span<const GridPoint> originals, double dmax) {
  return boundary_candidates(L, level_surface(L), represented, originals, dmax);
}

std::vector<BoundaryCandidate> boundary_candidates(const LevelGeometry& L, const LevelSurface& surface,
                                                   const Csr& represented,
                                                   std::span<const GridPoint> originals, double dmax) {
  const auto& triangles = surface.triangles;
  const Csr& around = surface.around;

  // Each vertex's candidacy is its own: on every core, in vertex order.
  return collect_in_order<BoundaryCandidate>(
      L.size(), 4096, [&](size_t first, size_t last, std::vector<BoundaryCandidate>& out) {
        std::vector<std::array<uint32_t, 3>> umbrella;
        for (auto v = static_cast<uint32_t>(first); v < last; ++v) {
          if (!surface.holds(L.boundary, v)) continue;
          umbrella.clear();
          for (uint32_t i : around.row(v)) umbrella.push_back(triangles[i]);
          const Umbrella u = umbrella_of(v, umbrella, L.points);
          const double area = norm(u.vector_area);
          if (!u.is_disk || area == 0) continue;
          const Vec3 normal = u.vector_area * (1.0 / area);
          double error = std::abs(dot(normal, to_vec(L.points[v]) - u.link_centroid));
          for (uint32_t k : represented.row(v))
            error = std::max(error, std::abs(dot(normal, to_vec(originals[k]) - u.link_centroid)));
          if (error <= dmax) out.push_back({v, error});
        }
      });
}

}  // namespace dtm
