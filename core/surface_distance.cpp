#include "surface_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <limits>
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
  double sum = 0;
  for (const GridPoint& q : queries) {
    const double d = std::sqrt(tree.squared_distance(to_point(q)));
    out.max = std::max(out.max, d);
    sum += d;
  }
  out.mean = sum / queries.size();
  return out;
}

}  // namespace dtm
