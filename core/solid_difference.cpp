#include "core/solid_difference.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

#include "core/reference_solid.h"
#include "mesh/geometry.h"

namespace dtm {
namespace {

using Cell = std::array<uint32_t, 4>;

std::vector<Cell> sorted_cells(std::span<const Cell> cells) {
  std::vector<Cell> out(cells.begin(), cells.end());
  for (Cell& c : out) std::sort(c.begin(), c.end());
  std::sort(out.begin(), out.end());
  return out;
}

double volume(std::span<const GridPoint> points, const Cell& c) {
  return static_cast<double>(abs_six_volume(points[c[0]], points[c[1]], points[c[2]], points[c[3]])) / 6;
}

// splitmix64: a small, fixed generator, so the estimate is reproducible.
uint64_t next_random(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9;
  z = (z ^ (z >> 27)) * 0x94d049bb133111eb;
  return z ^ (z >> 31);
}

double unit_random(uint64_t& state) { return static_cast<double>(next_random(state) >> 11) * 0x1p-53; }

// The volume of the cells of `cells` outside `other`, cells in `skip`
// (sorted) left out.
double outside_volume(std::span<const GridPoint> points, std::span<const Cell> cells,
                      std::span<const Cell> skip, const ReferenceSolid& other) {
  double out = 0;
  uint64_t state = 0;
  for (const Cell& c : cells) {
    if (std::binary_search(skip.begin(), skip.end(), c)) continue;
    const double v = volume(points, c);
    if (v == 0) continue;
    int outside = 0;
    for (int s = 0; s < kSolidDifferenceSamples; ++s) {
      // Uniform in the tetrahedron: barycentric weights are the gaps
      // between three sorted uniform numbers.
      std::array<double, 3> u = {unit_random(state), unit_random(state), unit_random(state)};
      std::sort(u.begin(), u.end());
      const std::array<double, 4> w = {u[0], u[1] - u[0], u[2] - u[1], 1 - u[2]};
      std::array<int64_t, 3> p4{};  // at four times the grid scale
      for (int axis = 0; axis < 3; ++axis) {
        double x = 0;
        for (int k = 0; k < 4; ++k) {
          const GridPoint& g = points[c[k]];
          x += w[k] * (axis == 0 ? g.x : axis == 1 ? g.y : g.z);
        }
        p4[axis] = std::llround(4 * x);
      }
      outside += !other.contains_point4(p4);
    }
    out += v * outside / kSolidDifferenceSamples;
  }
  return out;
}

}  // namespace

SolidDifference solid_difference(std::span<const GridPoint> points, std::span<const Cell> first,
                                 std::span<const Cell> second) {
  const std::vector<Cell> a = sorted_cells(first), b = sorted_cells(second);
  std::vector<Cell> shared;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(shared));
  const ReferenceSolid solid_a(points, a), solid_b(points, b);
  SolidDifference d;
  d.shared_cells = shared.size();
  d.only_first = outside_volume(points, a, shared, solid_b);
  d.only_second = outside_volume(points, b, shared, solid_a);
  for (const Cell& c : b) d.second_volume += volume(points, c);
  return d;
}

}  // namespace dtm
