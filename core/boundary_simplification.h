// Boundary simplification (seed paper §II.2), generalized to 3D.
//
// The paper's 2D test measures the distance from skipped boundary vertices to
// the chord between the two vertices that remain. Its 3D generalization here
// (spec/HIERARCHY.md §4 states it normatively):
//   * the umbrella of a boundary vertex v is the set of boundary faces of M_l
//     around it; v is a candidate only if the umbrella is a single disk (its
//     link is one closed cycle). Vertices with any other neighbourhood are kept;
//   * the chord becomes the link plane: through the centroid of the link
//     vertices, normal to the vector area of the umbrella (which equals the
//     vector area of the link polygon, the patch that will replace it). With
//     two link vertices this is exactly the 2D chord;
//   * the error of removing v is the largest distance to that plane of v and
//     of every original boundary vertex that v represents (the vertices that
//     earlier removals handed to it): the "vertices between the initial and
//     chord vertices" of the paper. v is a candidate when that error <= Dmax.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/level.h"

namespace dtm {

struct BoundaryCandidate {
  uint32_t vertex;  // local vertex of the level
  double error;     // grid units
};

// The removable boundary vertices of `level` for the tolerance `dmax` (grid
// units). `represented` has one row per vertex of the level: the original
// boundary points it stands for (indices into `originals`).
std::vector<BoundaryCandidate> boundary_candidates(const LevelGeometry& level, const Csr& represented,
                                                   std::span<const GridPoint> originals, double dmax);
// The same on the level's surface, already built (level_surface()).
std::vector<BoundaryCandidate> boundary_candidates(const LevelGeometry& level, const LevelSurface& surface,
                                                   const Csr& represented,
                                                   std::span<const GridPoint> originals, double dmax);

}  // namespace dtm
