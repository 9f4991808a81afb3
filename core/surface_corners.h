// A surface's triangles renumbered onto the corners they use, each once:
// a surface given in a larger point set's numbering (a reference's
// boundary, a level's surface) held on its own by the search structures of
// core/surface_distance.cpp and core/triangle_distance_tree.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"

namespace dtm {

struct SurfaceCorners {
  std::vector<GridPoint> corners;                  // ascending by their index in the larger set
  std::vector<std::array<uint32_t, 3>> triangles;  // into corners, in the order given
};

// On every core. `triangles` index `vertices`.
SurfaceCorners surface_corners(std::span<const GridPoint> vertices,
                               std::span<const std::array<uint32_t, 3>> triangles);

}  // namespace dtm
