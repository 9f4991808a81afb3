#include "surface_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>
#include <vector>

namespace dtm {
namespace {
using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 to_point(const GridPoint& p) { return {double(p.x), double(p.y), double(p.z)}; }
}  // namespace

DistanceSummary distance_to_surface(std::span<const GridPoint> vertices,
                                    std::span<const std::array<uint32_t, 3>> triangles,
                                    std::span<const GridPoint> queries) {
  DistanceSummary out;
  if (queries.empty()) return out;
  if (triangles.empty()) {
    out.max = out.mean = std::numeric_limits<double>::infinity();
    return out;
  }
  std::vector<Triangle> soup;
  soup.reserve(triangles.size());
  for (const auto& t : triangles)
    soup.emplace_back(to_point(vertices[t[0]]), to_point(vertices[t[1]]), to_point(vertices[t[2]]));
  Tree tree(soup.cbegin(), soup.cend());
  tree.accelerate_distance_queries();
  // Queries are independent and the tree is read-only once its search
  // structure exists (the first query builds it), so the rest run on every
  // core. Distances are summed afterwards in one order: the mean does not
  // depend on the thread count.
  std::vector<double> distance(queries.size());
  distance[0] = std::sqrt(tree.squared_distance(to_point(queries[0])));
  const size_t threads = std::clamp<size_t>(std::thread::hardware_concurrency(), 1, 8);
  const size_t chunk = (queries.size() + threads - 1) / threads;
  std::vector<std::thread> workers;
  for (size_t t = 0; t < threads; ++t)
    workers.emplace_back([&, t] {
      for (size_t i = std::max<size_t>(1, t * chunk); i < std::min(queries.size(), (t + 1) * chunk); ++i)
        distance[i] = std::sqrt(tree.squared_distance(to_point(queries[i])));
    });
  for (auto& w : workers) w.join();
  double sum = 0;
  for (double d : distance) {
    out.max = std::max(out.max, d);
    sum += d;
  }
  out.mean = sum / queries.size();
  return out;
}

}  // namespace dtm
