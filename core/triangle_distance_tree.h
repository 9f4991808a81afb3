// The squared distance from points to a fixed set of triangles, in little
// memory: a surface that many blocks and ranks hold whole (a reference
// solid's boundary: bunny_10m's has 1.4M triangles) costs about 30 bytes a
// triangle here, where CGAL's AABB tree with the k-d tree of hints that
// speeds its queries took about 110 (bunny_1m's reference boundary, 359,552
// triangles: 10.5 MiB against 37.6); as many queries near it take as long
// (0.27 s against 0.30 s on 2 cores), and it is built in half the time.
//
// A bounding volume hierarchy: the triangles in the Morton order of their
// boxes' centres, each node the triangles whose codes share a prefix (split
// where the next bit changes), at most eight to a leaf. Boxes are floats:
// grid coordinates lie below 2^24, where floats are exact. A query descends
// nearer box first and skips a box or triangle farther than the nearest
// triangle found.
//
// Each distance is the least, over the triangles, of the squared distance
// to CGAL's projection of the query onto the triangle (the arithmetic
// CGAL's AABB tree uses): what is skipped is farther by more than that
// projection's rounding. So it depends neither on the triangles' order nor
// on the tree: a surface and any part of it holding the nearest triangle
// give the same double.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"

namespace dtm {

class TriangleDistanceTree {
 public:
  TriangleDistanceTree() = default;
  // `triangles` index `vertices`; only the corners they use are kept.
  TriangleDistanceTree(std::span<const GridPoint> vertices,
                       std::span<const std::array<uint32_t, 3>> triangles);

  // Squared distance of each query, on every core; +infinity without a
  // triangle.
  std::vector<double> squared_distances(std::span<const GridPoint> queries) const;
  std::vector<double> squared_distances(std::span<const std::array<double, 3>> queries) const;
  // One query, on the calling thread.
  double squared_distance(const std::array<double, 3>& query) const;

  size_t triangles() const { return triangles_.size(); }
  // The corners the triangles use, ascending by their index in `vertices`
  // (surface_corners()'s order).
  std::span<const GridPoint> corners() const { return corners_; }
  // What it holds, in bytes.
  size_t bytes() const;

 private:
  // A node's box; a leaf's triangles [index, index + count), or (count 0)
  // its two children: the next node and node `index`.
  struct Node {
    std::array<float, 3> lo, hi;
    uint32_t index = 0, count = 0;
  };
  uint32_t make_node(std::span<const uint64_t> codes, uint32_t first, uint32_t last);
  static double box_squared(const Node& node, const std::array<double, 3>& q);
  // A bound below its distance: the distance to its box, less kSlack on
  // each axis (the cpp says why).
  double triangle_box_squared(size_t triangle, const std::array<double, 3>& q) const;
  double triangle_squared(size_t triangle, const std::array<double, 3>& q) const;

  std::vector<GridPoint> corners_;                  // the corners the triangles use
  std::vector<std::array<uint32_t, 3>> triangles_;  // into corners_, in Morton order
  std::vector<Node> nodes_;                         // depth first, the root first
};

}  // namespace dtm
