#include "mesh/geometry.h"

#include <algorithm>
#include <limits>

#include "mesh/predicates.h"

namespace dtm {

std::array<uint32_t, 4> sorted_positive(std::array<uint32_t, 4> cell, std::span<const GridPoint> points) {
  std::sort(cell.begin(), cell.end());
  if (orientation(points[cell[0]], points[cell[1]], points[cell[2]], points[cell[3]]) < 0)
    std::swap(cell[2], cell[3]);
  return cell;
}

std::array<uint32_t, 4> sorted_positive(std::array<uint32_t, 4> cell) {
  // Sorted by swaps, each one turning the cell inside out once.
  bool odd = false;
  for (int i = 1; i < 4; ++i)
    for (int j = i; j > 0 && cell[static_cast<size_t>(j - 1)] > cell[static_cast<size_t>(j)]; --j) {
      std::swap(cell[static_cast<size_t>(j - 1)], cell[static_cast<size_t>(j)]);
      odd = !odd;
    }
  if (odd) std::swap(cell[2], cell[3]);
  return cell;
}

bool spans_three_dimensions(std::span<const GridPoint> points) {
  // Find two points that differ, then a third off their line, then a fourth
  // off their plane; cross products of integer differences are exact in 128 bits.
  size_t i = 1;
  while (i < points.size() && points[i] == points[0]) ++i;
  if (i >= points.size()) return false;
  const GridPoint a = points[0], b = points[i];
  const Int128 ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  Int128 nx = 0, ny = 0, nz = 0;
  size_t j = i + 1;
  for (; j < points.size(); ++j) {
    const Int128 vx = points[j].x - a.x, vy = points[j].y - a.y, vz = points[j].z - a.z;
    nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    if (nx != 0 || ny != 0 || nz != 0) break;
  }
  for (size_t k = j + 1; k < points.size(); ++k) {
    const Int128 wx = points[k].x - a.x, wy = points[k].y - a.y, wz = points[k].z - a.z;
    if (nx * wx + ny * wy + nz * wz != 0) return true;
  }
  return false;
}

double signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return dot(b - a, cross(c - a, d - a)) / 6.0;
}

double circumradius(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 u = b - a, v = c - a, w = d - a;
  const double det = dot(u, cross(v, w));
  if (det == 0) return std::numeric_limits<double>::infinity();
  const Vec3 num = cross(v, w) * dot(u, u) + cross(w, u) * dot(v, v) + cross(u, v) * dot(w, w);
  return norm(num) / (2 * std::abs(det));
}

double canonical_circumradius(std::array<GridPoint, 4> c) {
  // Ascending (a sorting network: 5 compare-exchanges, no calls).
  auto order = [&c](int i, int j) {
    if (c[j] < c[i]) std::swap(c[i], c[j]);
  };
  order(0, 1), order(2, 3), order(0, 2), order(1, 3), order(1, 2);
  return circumradius(to_vec(c[0]), to_vec(c[1]), to_vec(c[2]), to_vec(c[3]));
}

double solid_angle(const Vec3& apex, const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 a = p - apex, b = q - apex, c = r - apex;
  const double la = norm(a), lb = norm(b), lc = norm(c);
  const double numerator = std::abs(dot(a, cross(b, c)));
  const double denominator = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
  return 2 * std::atan2(numerator, denominator);
}

std::array<double, 4> solid_angles(const std::array<Vec3, 4>& t) {
  return {solid_angle(t[0], t[1], t[2], t[3]), solid_angle(t[1], t[0], t[2], t[3]),
          solid_angle(t[2], t[0], t[1], t[3]), solid_angle(t[3], t[0], t[1], t[2])};
}

double smallest_solid_angle(std::span<const GridPoint> points, std::array<uint32_t, 4> cell) {
  std::sort(cell.begin(), cell.end(), [&](uint32_t a, uint32_t b) { return points[a] < points[b]; });
  const auto angles = solid_angles(
      {to_vec(points[cell[0]]), to_vec(points[cell[1]]), to_vec(points[cell[2]]), to_vec(points[cell[3]])});
  return std::min({angles[0], angles[1], angles[2], angles[3]});
}

}  // namespace dtm
