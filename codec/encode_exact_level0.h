// Under --exact, level 0 as the decoder builds it: the input's own cells.
// The hierarchy's builder measures the Delaunay carving the exact cells are
// coded against; the report gives the figures of the cells the user gets
// back (their number and shape, and a solid equal to the input's).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "codec/encode.h"
#include "common/grid.h"
#include "core/solid_difference.h"

namespace dtm {

struct ExactLevel0 {
  uint64_t cells = 0;
  double avg_min_solid_angle = 0;  // steradians
  double min_solid_angle = 0;
  double volume = 0;  // grid units cubed
  // Measured where the reference's boundary is more than the solid's (its
  // regions' interfaces); else the reference's count.
  std::optional<uint64_t> boundary_vertices;

  // Level 0's row: the builder's figures for the Delaunay carving replaced
  // by the exact cells'. Its boundary is the reference's (the same cells):
  // no distance to it, and as many boundary vertices.
  void describe(LevelReport& level) const;
  // Level 0's solid against the input's: the same cells.
  SolidDifference difference() const;
};

// The figures of `cells` (grid-point indices), measured on every core; the
// same bits for any number of threads. `regions`: the reference has
// several (its boundary holds their interfaces).
ExactLevel0 measure_exact_level0(std::span<const GridPoint> points,
                                 std::span<const std::array<uint32_t, 4>> cells, bool regions);

}  // namespace dtm
