// check_spans_3d (input.h), with CGAL's exact orientation predicate: a
// coplanar input must be caught however large or skewed its coordinates.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>

#include "format_error.h"
#include "input.h"

namespace dtm {

void check_spans_3d(const std::vector<InputPoint>& points, const std::string& path) {
  using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;
  std::vector<Point> p;
  p.reserve(points.size());
  for (const InputPoint& q : points) p.emplace_back(q.x, q.y, q.z);
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 4)
    throw FormatError(path + ": " + std::to_string(p.size()) + " distinct point" +
                      (p.size() == 1 ? "" : "s") + " (of " + std::to_string(points.size()) +
                      "); a tetrahedral mesh needs at least 4");
  // p[0] != p[1]; find a point off their line, then one off their plane.
  size_t c = 2;
  while (c < p.size() && CGAL::collinear(p[0], p[1], p[c])) ++c;
  if (c == p.size())
    throw FormatError(path + ": all " + std::to_string(p.size()) + " distinct points are collinear");
  for (size_t d = 2; d < p.size(); ++d)
    if (CGAL::orientation(p[0], p[1], p[c], p[d]) != CGAL::COPLANAR) return;
  throw FormatError(path + ": all " + std::to_string(p.size()) +
                    " distinct points are coplanar; a tetrahedral mesh needs a volume");
}

}  // namespace dtm
