// How far level 0's solid is from the input's: the volume of the symmetric
// difference of two unions of tetrahedra over the same grid points. A
// measurement for the report (issue 12: level 0 is the input wherever the
// input's cells are Delaunay). The codec's builder measures its level 0 with
// carved_difference (it has the solid and level 0's tetrahedralization at
// hand); no level depends on it.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "common/grid.h"
#include "core/reference_solid.h"
#include "mesh/delaunay.h"

namespace dtm {

struct SolidDifference {
  // Grid units cubed.
  double only_first = 0;      // inside `first`, outside `second`
  double only_second = 0;     // inside `second`, outside `first`
  double second_volume = 0;   // the whole of `second`
  uint64_t shared_cells = 0;  // tetrahedra both list (same four corners)
  int samples_per_cell = 0;   // how many points each other tetrahedron was sampled at
  double symmetric() const { return only_first + only_second; }
};

// Tetrahedra listed by both sets cancel exactly. Each other tetrahedron is
// sampled at the same number of points uniformly distributed in it (a fixed
// pseudo-random sequence per tetrahedron, so the figure is reproducible;
// positions rounded to a quarter of a grid step), and the share of them
// outside the other set is counted. Exact where the two sets meet along
// whole tetrahedra; a tetrahedron the other set's boundary cuts is measured
// without bias, to within a few percent of its volume with the most
// samples. The samples per tetrahedron: kSolidDifferenceSamples, fewer when
// that would pass kSolidDifferenceSampleBudget points in all (large meshes:
// their many tetrahedra average the error out), never below
// kSolidDifferenceFewestSamples.
inline constexpr int kSolidDifferenceSamples = 400;
inline constexpr size_t kSolidDifferenceSampleBudget = 500'000;
inline constexpr int kSolidDifferenceFewestSamples = 4;
SolidDifference solid_difference(std::span<const GridPoint> points,
                                 std::span<const std::array<uint32_t, 4>> first,
                                 std::span<const std::array<uint32_t, 4>> second);

// Per cell of `dt` (vertex ids index the points): the index of the
// tetrahedron of `tets` with the same four corners, or -1.
std::vector<int32_t> matching_tetrahedra(const TetMesh& dt, size_t points,
                                         std::span<const std::array<uint32_t, 4>> tets);

// The same figures for a carved Delaunay tetrahedralization (the cells of
// `dt` flagged in `kept`, over `points`) against `tets`, given the solid
// made of `tets` and matching_tetrahedra(dt, ..., tets): the sampled points
// of the tetrahedra `tets` has alone are located by walking `dt` (a
// visibility walk, which ends in a Delaunay tetrahedralization), the others
// by `solid`. Samples as solid_difference's; the figure is the same
// estimate, with no solid built for `dt`.
SolidDifference carved_difference(std::span<const GridPoint> points, const TetMesh& dt,
                                  std::span<const uint8_t> kept,
                                  std::span<const std::array<uint32_t, 4>> tets, const Solid& solid,
                                  std::span<const int32_t> match);

}  // namespace dtm
