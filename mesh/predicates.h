// Exact predicates on grid points for code that walks a mesh the
// triangulation did not make (codec/sections/exact_cell_coder.h): the
// orientation of four points and the side of a sphere. Both are exact, so
// that an encoder and a decoder on any machine (native or WebAssembly)
// decide alike.
#pragma once

#include <array>

#include "common/grid.h"

namespace dtm {

// +1 when d lies on the positive side of the plane through a, b, c (the
// tetrahedron abcd is positively oriented, as a Delaunay cell is), -1 on
// the negative side, 0 in the plane. 128-bit integer arithmetic.
int orientation(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d);

// For a positively oriented tetrahedron abcd: +1 when e lies inside its
// circumsphere, -1 outside, 0 on it (CGAL's exact predicate).
int side_of_sphere(const GridPoint& a, const GridPoint& b, const GridPoint& c, const GridPoint& d,
                   const GridPoint& e);

// True when the interiors of the tetrahedra a and b (each with positive
// volume, either orientation) have a point in common; false when they are
// apart or only touch (a shared corner, edge or face, or one lying on the
// other's face). Exact, for grid coordinates below 2^kMaxQBits: two convex
// polytopes' interiors are disjoint exactly when a plane with a face's
// normal or the cross product of an edge of each separates them.
bool interiors_meet(const std::array<GridPoint, 4>& a, const std::array<GridPoint, 4>& b);

}  // namespace dtm
