// What removing one vertex of a level does, seen before it is done: the cells
// that refill its cavity (the Delaunay tetrahedralization without it, in that
// region) and how the level's carving treats them. The removal guards judge a
// candidate on this: the quality guard on the refill's solid angles, the
// shape guard on the surface the decoder will show.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/csr.h"
#include "common/grid.h"
#include "core/level.h"
#include "core/reference_solid.h"
#include "core/surface_distance.h"

namespace dtm {

struct Refill {
  std::vector<std::array<uint32_t, 4>> cells;  // local vertices of the level; empty: a flat hull tip
  std::vector<uint8_t> kept;                   // per cell, with a reference solid: the solid keeps it
  // The boundary faces of the carved level inside the cavity after the
  // removal: faces of kept refill cells against removed ones, the cavity's
  // outside or the hull (orientation unspecified).
  std::vector<std::array<uint32_t, 3>> surface;
};

// The refill of the cavity of v; `solid` null: carved by alpha (L.alpha).
Refill refill_of(const LevelGeometry& L, uint32_t v, const ReferenceSolid* solid);

// The shape guard (spec/HIERARCHY.md §5): removing v keeps the carved
// surface where it was. An interior vertex's refill must be kept whole (no
// new surface inside the solid). For a boundary vertex, v and the original
// boundary points that v and its neighbours represent (`represented`) must
// lie within `dmax` of the surface after the removal (the refill's surface
// and the level's triangles around v's neighbours that do not touch v), and
// the refill's surface within `dmax` of the reference's: its vertices and
// its triangles' centroids (rounded to the grid).
bool shape_allows(const LevelGeometry& L, const LevelSurface& surface, uint32_t v, const Refill& refill,
                  std::span<const GridPoint> represented, const FixedSurface& reference, double dmax);

// Distance from p to triangle (a, b, c).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace dtm
