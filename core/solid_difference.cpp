#include "core/solid_difference.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <vector>

#include "common/atomic_counts.h"
#include "common/csr.h"
#include "common/first_touch.h"
#include "common/parallel_for.h"
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

// The cells' volume summed exactly (six times each as an integer) on every
// core: the same figure in any order and on any number of threads.
double total_volume(std::span<const GridPoint> points, std::span<const Cell> cells) {
  constexpr size_t kRange = size_t{1} << 16;
  std::vector<Int128> per_range((cells.size() + kRange - 1) / kRange, 0);
  parallel_ranges(cells.size(), kRange, [&](size_t first, size_t last) {
    Int128 sum = 0;
    for (size_t k = first; k < last; ++k)
      sum +=
          abs_six_volume(points[cells[k][0]], points[cells[k][1]], points[cells[k][2]], points[cells[k][3]]);
    per_range[first / kRange] = sum;
  });
  Int128 sum = 0;
  for (const Int128& s : per_range) sum += s;
  return static_cast<double>(sum) / 6;
}

// splitmix64: a small, fixed generator, so the estimate is reproducible.
uint64_t next_random(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9;
  z = (z ^ (z >> 27)) * 0x94d049bb133111eb;
  return z ^ (z >> 31);
}

double unit_random(uint64_t& state) { return static_cast<double>(next_random(state) >> 11) * 0x1p-53; }

// The cells of `cells` not in `skip` (sorted).
std::vector<uint32_t> unshared(std::span<const Cell> cells, std::span<const Cell> skip) {
  std::vector<uint32_t> out;
  for (uint32_t k = 0; k < cells.size(); ++k)
    if (!std::binary_search(skip.begin(), skip.end(), cells[k])) out.push_back(k);
  return out;
}

// The seed of a cell's samples: its corners, whatever their order and the
// cell's place in its list.
uint64_t seed_of(Cell c) {
  std::sort(c.begin(), c.end());
  uint64_t state = (uint64_t{c[0]} << 32 | c[1]) ^ 0x2545f4914f6cdd1dull;
  state = next_random(state) ^ (uint64_t{c[2]} << 32 | c[3]);
  return next_random(state);
}

// The volume of the cells `which` of `cells` outside a solid, each sampled
// at `samples` points from a sequence seeded by its corners (the figure does
// not depend on how the work is split between cores, nor, but for rounding,
// on the order the cells are listed in). `inside(p4, cell)`:
// whether p / 4 is in the solid (`cell`: the sampled cell's index).
template <class Inside>
double outside_volume(std::span<const GridPoint> points, std::span<const Cell> cells,
                      std::span<const uint32_t> which, int samples, const Inside& inside) {
  std::vector<double> per_cell(which.size(), 0);
  parallel_for(
      which.size(),
      [&](size_t i) {
        Cell c = cells[which[i]];
        std::sort(c.begin(), c.end());  // the samples do not depend on the corners' order
        const double v = volume(points, c);
        if (v == 0) return;
        uint64_t state = seed_of(c);
        int outside = 0;
        for (int s = 0; s < samples; ++s) {
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
          outside += !inside(p4, which[i]);
        }
        per_cell[i] = v * outside / samples;
      },
      64);
  double out = 0;
  for (double v : per_cell) out += v;
  return out;
}

int samples_for(size_t cells) {
  return static_cast<int>(std::clamp<size_t>(kSolidDifferenceSampleBudget / std::max<size_t>(1, cells),
                                             kSolidDifferenceFewestSamples, kSolidDifferenceSamples));
}

using P4 = std::array<int64_t, 3>;

int orientation(const P4& a, const P4& b, const P4& c, const P4& d) {
  const Int128 ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const Int128 vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  const Int128 wx = d[0] - a[0], wy = d[1] - a[1], wz = d[2] - a[2];
  const Int128 det = ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx);
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

P4 times4(const GridPoint& p) { return {4 * int64_t{p.x}, 4 * int64_t{p.y}, 4 * int64_t{p.z}}; }

// The cell of `dt` (positively oriented) whose closure holds p / 4, walking
// from `start` across any face p lies strictly beyond; -1 when the walk
// leaves the convex hull (p is in no cell).
int64_t locate(std::span<const GridPoint> points, const TetMesh& dt, int64_t start, const P4& p) {
  int64_t c = start;
  for (size_t steps = 0; steps <= dt.cells.size(); ++steps) {
    const auto& k = dt.cells[static_cast<size_t>(c)];
    const P4 v[4] = {times4(points[k[0]]), times4(points[k[1]]), times4(points[k[2]]), times4(points[k[3]])};
    int beyond = -1;
    for (int i = 0; i < 4 && beyond < 0; ++i) {
      P4 w[4] = {v[0], v[1], v[2], v[3]};
      w[i] = p;
      if (orientation(w[0], w[1], w[2], w[3]) < 0) beyond = i;
    }
    if (beyond < 0) return c;
    c = dt.neighbors[static_cast<size_t>(c)][beyond];
    if (c < 0) return -1;
  }
  return -1;  // not reached: a visibility walk ends in a Delaunay tetrahedralization
}

}  // namespace

SolidDifference solid_difference(std::span<const GridPoint> points, std::span<const Cell> first,
                                 std::span<const Cell> second) {
  const std::vector<Cell> a = sorted_cells(first), b = sorted_cells(second);
  std::vector<Cell> shared;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(shared));
  const ReferenceSolid solid_a(points, a), solid_b(points, b);
  const std::vector<uint32_t> only_a = unshared(a, shared), only_b = unshared(b, shared);
  const int samples = samples_for(only_a.size() + only_b.size());
  SolidDifference d;
  d.shared_cells = shared.size();
  d.samples_per_cell = samples;
  d.only_first = outside_volume(points, a, only_a, samples,
                                [&](const P4& p, uint32_t) { return solid_b.contains_point4(p); });
  d.only_second = outside_volume(points, b, only_b, samples,
                                 [&](const P4& p, uint32_t) { return solid_a.contains_point4(p); });
  d.second_volume = total_volume(points, b);
  return d;
}

std::vector<int32_t> matching_tetrahedra(const TetMesh& dt, size_t points, std::span<const Cell> tets) {
  // The tetrahedra by their smallest corner: a cell's match, if any, is
  // among the few that share its smallest corner.
  auto sorted = [](Cell c) {
    std::sort(c.begin(), c.end());
    return c;
  };
  const Csr by_corner = build_csr(points, [&](auto&& emit) {
    for (uint32_t k = 0; k < tets.size(); ++k) emit(*std::min_element(tets[k].begin(), tets[k].end()), k);
  });
  std::vector<int32_t> match;
  assign_on_every_core(match, dt.cells.size(), -1);
  parallel_for((dt.cells.size() + 4095) / 4096,
               [&](size_t block) {
                 for (size_t c = block * 4096; c < std::min(dt.cells.size(), block * 4096 + 4096); ++c) {
                   const Cell key = sorted(dt.cells[c]);
                   for (uint32_t k : by_corner.row(key[0]))
                     if (sorted(tets[k]) == key) {
                       match[c] = static_cast<int32_t>(k);
                       break;
                     }
                 }
               },
               2);
  return match;
}

SolidDifference carved_difference(std::span<const GridPoint> points, const TetMesh& dt,
                                  std::span<const uint8_t> kept, std::span<const Cell> tets,
                                  const Solid& solid, std::span<const int32_t> match) {
  // Every pass on every core (each was a serial stretch of the encoder's
  // level 0: 6.3M cells at bunny_1m), in ranges whose results join in order.
  constexpr size_t kRange = size_t{1} << 16;
  std::vector<uint8_t> tet_shared(tets.size(), 0);
  SolidDifference d;
  const std::vector<uint32_t> only_dt = collect_in_order<uint32_t>(
      dt.cells.size(), kRange, [&](size_t first, size_t last, std::vector<uint32_t>& out) {
        for (size_t c = first; c < last; ++c) {
          if (!kept[c]) continue;
          if (match[c] >= 0)
            atomic_store(tet_shared[static_cast<size_t>(match[c])], 1);
          else
            out.push_back(static_cast<uint32_t>(c));
        }
      });
  const std::vector<uint32_t> only_tets = collect_in_order<uint32_t>(
      tets.size(), kRange, [&](size_t first, size_t last, std::vector<uint32_t>& out) {
        for (size_t k = first; k < last; ++k)
          if (!tet_shared[k]) out.push_back(static_cast<uint32_t>(k));
      });
  d.shared_cells = tets.size() - only_tets.size();
  // Where each walk starts: the first cell at the sampled tetrahedron's
  // smallest corner (whatever order it lists its corners in).
  constexpr uint32_t kNoCell = UINT32_MAX;
  std::vector<uint32_t> cell_at(points.size(), kNoCell);
  parallel_ranges(dt.cells.size(), kRange, [&](size_t first, size_t last) {
    for (size_t c = first; c < last; ++c)
      for (uint32_t v : dt.cells[c]) atomic_store_min(cell_at[v], static_cast<uint32_t>(c));
  });
  const int samples = samples_for(only_dt.size() + only_tets.size());
  d.samples_per_cell = samples;
  d.only_first = outside_volume(points, dt.cells, only_dt, samples,
                                [&](const P4& p, uint32_t) { return solid.contains_point4(p); });
  d.only_second = outside_volume(points, tets, only_tets, samples, [&](const P4& p, uint32_t k) {
    const uint32_t start = cell_at[*std::min_element(tets[k].begin(), tets[k].end())];
    if (start == kNoCell) return false;
    const int64_t c = locate(points, dt, start, p);
    return c >= 0 && kept[static_cast<size_t>(c)] != 0;
  });
  d.second_volume = total_volume(points, tets);
  return d;
}

}  // namespace dtm
