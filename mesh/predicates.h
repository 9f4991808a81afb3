// Exact predicates on grid points for code that walks a mesh the
// triangulation did not make (codec/sections/exact_cell_coder.h): the
// orientation of four points and the side of a sphere. Both are exact, so
// that an encoder and a decoder on any machine (native or WebAssembly)
// decide alike.
#pragma once

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

}  // namespace dtm
