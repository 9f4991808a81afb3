// How far level 0's solid is from the input's: the volume of the symmetric
// difference of two unions of tetrahedra over the same grid points. A
// measurement for the report (issue 12: level 0 is the input wherever the
// input's cells are Delaunay); the hierarchy does not use it.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "common/grid.h"

namespace dtm {

struct SolidDifference {
  // Grid units cubed.
  double only_first = 0;      // inside `first`, outside `second`
  double only_second = 0;     // inside `second`, outside `first`
  double second_volume = 0;   // the whole of `second`
  uint64_t shared_cells = 0;  // tetrahedra both list (same four corners)
  double symmetric() const { return only_first + only_second; }
};

// Tetrahedra listed by both sets cancel exactly. Each other tetrahedron is
// sampled at kSolidDifferenceSamples points uniformly distributed in it
// (a fixed pseudo-random sequence, so the figure is reproducible; positions
// rounded to a quarter of a grid step), and the share of them outside the
// other set is counted. Exact where the two sets meet along whole
// tetrahedra; a tetrahedron the other set's boundary cuts is measured to
// within a few percent of its volume, without bias.
inline constexpr int kSolidDifferenceSamples = 400;
SolidDifference solid_difference(std::span<const GridPoint> points,
                                 std::span<const std::array<uint32_t, 4>> first,
                                 std::span<const std::array<uint32_t, 4>> second);

}  // namespace dtm
