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
  // removal (orientation unspecified): faces between a kept and a removed
  // cell, on either side of the cavity's border, and kept cells' faces on
  // the hull.
  std::vector<std::array<uint32_t, 3>> surface;
  // The cavity's border faces (vertices sorted, the list sorted): the
  // removal decides anew whether each of them is on the surface.
  std::vector<std::array<uint32_t, 3>> border;
};

// The refill of the cavity of v; `solid` null: carved by alpha (L.alpha).
Refill refill_of(const LevelGeometry& L, uint32_t v, const ReferenceSolid* solid);

// The shape guard (spec/HIERARCHY.md §6.2): removing v keeps the carved
// surface where it was. An interior vertex's refill must be kept whole (no
// new surface inside the solid). For a boundary vertex, v and the original
// boundary points `at_risk` must lie within `dmax` of the surface after the
// removal (the refill's surface and the level's triangles around v's
// neighbours that neither touch v nor lie on the cavity's border), and the
// refill's surface within `dmax` of the reference's: its vertices and its
// triangles' centroids (rounded to the grid).
bool shape_allows(const LevelGeometry& L, const LevelSurface& surface, uint32_t v, const Refill& refill,
                  std::span<const GridPoint> at_risk, const FixedSurface& reference, double dmax);

// The surface triangles removing v takes away or re-decides: those around v
// and those on its cavity's border.
std::vector<std::array<uint32_t, 3>> triangles_at_stake(const LevelSurface& surface, const LevelGeometry& L,
                                                        uint32_t v, const Refill& refill);

// Distance from p to triangle (a, b, c).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace dtm
