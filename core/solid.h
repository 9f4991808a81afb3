// A solid every codec level is carved to (spec/HIERARCHY.md §2.1): a cell of
// a level's Delaunay tetrahedralization is kept when its centroid lies in it.
// Two kinds: the input's tetrahedra (reference_solid.h) and a scan's voxels
// (voxel_solid.h). Points are asked at four times the grid's scale, where a
// centroid of grid points is integral: the verdicts are exact.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"
#include "mesh/delaunay.h"

namespace dtm {

class Solid {
 public:
  virtual ~Solid() = default;

  // True if the point p / 4 (p at four times the grid scale) is in the solid.
  virtual bool contains_point4(const std::array<int64_t, 3>& p) const = 0;

  // The region holding p / 4: 0 outside the solid, else 1 + the index of
  // the region (a solid of several regions, region_solid.h; one region: 1).
  virtual uint8_t region_point4(const std::array<int64_t, 3>& p) const { return contains_point4(p) ? 1 : 0; }
  uint8_t region_of_centroid(const GridPoint& a, const GridPoint& b, const GridPoint& c,
                             const GridPoint& d) const {
    return region_point4(
        {int64_t{a.x} + b.x + c.x + d.x, int64_t{a.y} + b.y + c.y + d.y, int64_t{a.z} + b.z + c.z + d.z});
  }

  // True if the centroid of the tetrahedron (a, b, c, d) is in the solid.
  bool contains_centroid(const GridPoint& a, const GridPoint& b, const GridPoint& c,
                         const GridPoint& d) const {
    return contains_point4(
        {int64_t{a.x} + b.x + c.x + d.x, int64_t{a.y} + b.y + c.y + d.y, int64_t{a.z} + b.z + c.z + d.z});
  }

  // Per cell of `dt` (vertex ids index `points`): its region (0: the solid
  // does not keep it; region_point4()).
  // Computed on every core. Work that may be handed a guessing solid
  // settles it afterwards (below).
  std::vector<uint8_t> verdicts(const TetMesh& dt, std::span<const GridPoint> points) const;

  // Called by work that carves, after each pass of questions, where its
  // answers decide what it does next. A solid that could only guess some of
  // them (codec/blocks/reference_questions.h) says so with a status that is
  // not ok, and the work returns it at once: the rest would run on guesses.
  virtual Status settle() const { return Status::Ok(); }
  // Gets the answers to what the last pass could only guess, where the
  // solid can ask for them at once (the ranks of a run answering while
  // they work): true when it did, and the pass must be run again.
  virtual bool ask() const { return false; }
};

// Runs `pass`, a pass of questions to `solid` whose answers decide what the
// work does next, again while the solid gets answers it had only guessed,
// then settles it (above).
template <class Pass>
Status settled_pass(const Solid& solid, Pass&& pass) {
  pass();
  while (solid.ask()) pass();
  return solid.settle();
}

}  // namespace dtm
