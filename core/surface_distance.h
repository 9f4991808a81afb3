// Distance from points to a triangulated surface, for the shape error of a
// level (largest distance from the level-0 boundary vertices to the level's
// boundary surface). A measurement, so inexact arithmetic is fine; CGAL's
// AABB tree does the work and stays inside surface_distance.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "grid.h"

namespace dtm {

struct DistanceSummary {
  double max = 0;   // grid units; +infinity when there is no surface
  double mean = 0;
};

DistanceSummary distance_to_surface(std::span<const GridPoint> vertices,
                                    std::span<const std::array<uint32_t, 3>> triangles,
                                    std::span<const GridPoint> queries);

}  // namespace dtm
