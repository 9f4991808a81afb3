// Small exact-input geometry on grid points: tetrahedron volume, circumradius
// and solid angles. Inputs are integer grid coordinates (exact in double up
// to 2^24), so every quantity is computed identically on any machine.
#pragma once

#include <array>
#include <cmath>
#include <span>

#include "common/grid.h"

namespace dtm {

struct Vec3 {
  double x = 0, y = 0, z = 0;
  Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
};

inline Vec3 to_vec(const GridPoint& p) { return {double(p.x), double(p.y), double(p.z)}; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kFullSolidAngle = 4 * kPi;
// Every solid angle of the regular tetrahedron: 3 arccos(1/3) - pi.
inline constexpr double kRegularTetSolidAngle = 0.5512855984325308;

using Int128 = __int128;

// 6 x |volume| of a tetrahedron of grid points, exactly: coordinate
// differences need 25 bits, their triple products 75, so 128 bits hold the
// determinant.
inline Int128 abs_six_volume(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d) {
  const Int128 ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const Int128 vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
  const Int128 wx = d.x - a.x, wy = d.y - a.y, wz = d.z - a.z;
  const Int128 det = ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx);
  return det < 0 ? -det : det;
}

// A positively oriented cell's corners in ascending order, but for the last
// two swapped when that order would turn it inside out (exact): one way of
// writing a cell, whatever order a triangulation lists its corners in.
std::array<uint32_t, 4> sorted_positive(std::array<uint32_t, 4> cell, std::span<const GridPoint> points);
// The same for a cell known to be positively oriented (a TetMesh's): the
// parity of the sort tells the orientation, no point is read.
std::array<uint32_t, 4> sorted_positive(std::array<uint32_t, 4> cell);

// True if the points do not all lie in one plane (exact).
bool spans_three_dimensions(std::span<const GridPoint> points);

// Signed volume (eq. 2.5): positive for a positively oriented tetrahedron.
double signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// Radius of the circumscribed sphere; +infinity for a flat tetrahedron.
double circumradius(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The circumradius as the carving computes it (spec/HIERARCHY.md §2): on the
// corners sorted lexicographically, so the value depends on the four points
// only, not on the order a triangulation lists them in.
double canonical_circumradius(std::array<GridPoint, 4> corners);

// Solid angle at `apex` subtended by triangle (p, q, r), in steradians, by the
// Van Oosterom-Strackee formula (equal to eq. 2.2-2.3, better conditioned).
double solid_angle(const Vec3& apex, const Vec3& p, const Vec3& q, const Vec3& r);

// The four solid angles of a tetrahedron, at vertex i for i = 0..3.
std::array<double, 4> solid_angles(const std::array<Vec3, 4>& t);

// The smallest solid angle of a cell, on its corners in lexicographic
// order (as analyze_level computes it: the same bits whatever the order a
// triangulation lists them in).
double smallest_solid_angle(std::span<const GridPoint> points, std::array<uint32_t, 4> cell);

}  // namespace dtm
