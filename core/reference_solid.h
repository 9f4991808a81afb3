// The solid every level is carved to (DESIGN.md §3.3, spec/HIERARCHY.md §3):
// a set of tetrahedra over grid points (the input's own, or level 0's alpha
// carving when the input has none). A cell of a level's Delaunay
// tetrahedralization is kept when its centroid lies in the closed union of
// these tetrahedra. The test is exact: centroids are compared at four times
// the grid's scale, in 128-bit integers.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/csr.h"
#include "common/grid.h"
#include "mesh/delaunay.h"

namespace dtm {

class ReferenceSolid {
 public:
  // `cells` index `points`; flat cells are ignored (they hold no volume).
  ReferenceSolid(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells);

  // True if the centroid of the tetrahedron (a, b, c, d) is in the solid.
  bool contains_centroid(const GridPoint& a, const GridPoint& b, const GridPoint& c,
                         const GridPoint& d) const;

  // True if the point p / 4 (p at four times the grid scale) is in the solid.
  bool contains_point4(const std::array<int64_t, 3>& p) const { return contains4(p); }

  size_t tetrahedra() const { return tets_.size(); }

  // Per cell of `dt` (vertex ids index `points`): 1 if the solid keeps it.
  std::vector<uint8_t> verdicts(const TetMesh& dt, std::span<const GridPoint> points) const;

 private:
  // Corners at four times the grid scale, so that a centroid is integral.
  using Point4 = std::array<int64_t, 3>;
  bool contains4(const Point4& p) const;
  size_t bucket_of(const Point4& p) const;
  void sort_along_morton_curve();

  std::vector<std::array<Point4, 4>> tets_;   // positively oriented
  std::vector<std::array<Point4, 2>> boxes_;  // each tetrahedron's bounding box: a cheap first test
  // A uniform grid of buckets over the solid's bounding box, each listing
  // the tetrahedra whose bounding box meets it (CSR).
  Point4 lo_{}, hi_{};
  std::array<int64_t, 3> dims_{1, 1, 1};
  int64_t bucket_size_ = 1;
  // Every coordinate (x4) under 2^18: orientations fit in 64-bit integers.
  // (Queries outside the bounding box are refused before any orientation.)
  bool small_ = false;
  Csr buckets_;
};

}  // namespace dtm
