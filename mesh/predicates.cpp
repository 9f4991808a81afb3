#include "mesh/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>

#include "mesh/geometry.h"

namespace dtm {
namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
// Grid coordinates are integers below 2^24: exact in a double.
Kernel::Point_3 point(const GridPoint& p) { return {double(p.x), double(p.y), double(p.z)}; }

// Integer vectors between grid points: a difference's components are below
// 2^24, a cross product's below 2^49, a dot product of the two below 2^75.
struct Vec {
  int64_t x = 0, y = 0, z = 0;
};
Vec operator-(const GridPoint& a, const GridPoint& b) {
  return {int64_t{a.x} - b.x, int64_t{a.y} - b.y, int64_t{a.z} - b.z};
}
Vec cross(const Vec& u, const Vec& v) {
  return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}
Int128 dot(const Vec& n, const Vec& d) { return Int128{n.x} * d.x + Int128{n.y} * d.y + Int128{n.z} * d.z; }

using Tet = std::array<GridPoint, 4>;

// True when a plane with normal n puts a and b on opposite closed sides.
bool separates(const Vec& n, const Tet& a, const Tet& b) {
  if (n.x == 0 && n.y == 0 && n.z == 0) return false;
  const GridPoint& o = a[0];
  Int128 a_low = 0, a_high = 0;  // a[0] projects to 0
  for (size_t i = 1; i < 4; ++i) {
    const Int128 s = dot(n, a[i] - o);
    a_low = std::min(a_low, s);
    a_high = std::max(a_high, s);
  }
  Int128 b_low = dot(n, b[0] - o), b_high = b_low;
  for (size_t i = 1; i < 4; ++i) {
    const Int128 s = dot(n, b[i] - o);
    b_low = std::min(b_low, s);
    b_high = std::max(b_high, s);
    // Both sides of a's range: no plane of this normal separates them.
    if (b_low < a_high && b_high > a_low) return false;
  }
  return a_high <= b_low || b_high <= a_low;
}

// The normals of a's faces: a face's plane separates exactly when b lies on
// its outer closed side.
bool a_face_separates(const Tet& a, const Tet& b) {
  constexpr size_t kFace[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (const auto& f : kFace)
    if (separates(cross(a[f[1]] - a[f[0]], a[f[2]] - a[f[0]]), a, b)) return true;
  return false;
}

}  // namespace

bool interiors_meet(const Tet& a, const Tet& b) {
  if (a_face_separates(a, b) || a_face_separates(b, a)) return false;
  constexpr size_t kEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (const auto& e : kEdge) {
    const Vec u = a[e[1]] - a[e[0]];
    for (const auto& g : kEdge)
      if (separates(cross(u, b[g[1]] - b[g[0]]), a, b)) return false;
  }
  return true;
}

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
