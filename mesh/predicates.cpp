#include "mesh/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "mesh/geometry.h"

namespace dtm {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// Grid coordinates are integers below 2^24: exact in a double.
Kernel::Point_3 point(const GridPoint& p) { return {double(p.x), double(p.y), double(p.z)}; }
}  // namespace

int orientation(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d) {
  const Int128 ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const Int128 vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const Int128 wx = d.x - a.x, wy = d.y - a.y, wz = d.z - a.z;
  const Int128 det = ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx);
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

int side_of_sphere(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d,
                   const GridPoint& e) {
  switch (CGAL::side_of_oriented_sphere(point(a), point(b), point(c), point(d), point(e))) {
    case CGAL::ON_POSITIVE_SIDE:
      return 1;
    case CGAL::ON_NEGATIVE_SIDE:
      return -1;
    default:
      return 0;
  }
}

}  // namespace dtm
