#include "core/triangle_distance_tree.h"

#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <bit>
#include <limits>
#include <utility>

#include "common/bits_by_three.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/release.h"
#include "common/status.h"
#include "core/surface_corners.h"

namespace dtm {
namespace {

using K = CGAL::Simple_cartesian<double>;

constexpr size_t kLeafTriangles = 8;
constexpr size_t kRange = 8192;       // items per range of the loops on every core
constexpr size_t kQueryRange = 1024;  // queries per range: each is a search
// A box or triangle is skipped only when it is farther than the nearest
// triangle found by more than this (grid units, on each axis). CGAL's
// projection onto a triangle in a plane x = c can round x a few units in
// the last place toward the query, so the squared distance it computes can
// fall that little below the distance to the triangle's box; grid
// coordinates lie below 2^24, where a few such units are below 2^-26.
constexpr double kSlack = 1.0 / 65536;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr float kInfinityF = std::numeric_limits<float>::infinity();

// A 63-bit Morton code: the 21 highest bits of each coordinate that the
// points use, interleaved. It only orders the triangles (neighbours near
// in the order lie near in space), so the bits dropped cost nothing but a
// looser tree.
uint64_t morton63(const std::array<int64_t, 3>& twice_centre, int shift) {
  return spread_by_three(static_cast<uint64_t>(twice_centre[0]) >> shift) |
         spread_by_three(static_cast<uint64_t>(twice_centre[1]) >> shift) << 1 |
         spread_by_three(static_cast<uint64_t>(twice_centre[2]) >> shift) << 2;
}

}  // namespace

TriangleDistanceTree::TriangleDistanceTree(std::span<const GridPoint> vertices,
                                           std::span<const std::array<uint32_t, 3>> triangles) {
  if (triangles.empty()) return;
  // Node numbers (at most twice the triangles) are 32 bits.
  DTM_CHECK(triangles.size() < (size_t{1} << 31));
  SurfaceCorners surface = surface_corners(vertices, triangles);
  corners_ = std::move(surface.corners);
  // Each triangle's place along the Morton curve of its box's centre (twice
  // it: integers), ties by its index.
  int64_t top = 1;
  for (const GridPoint& p : corners_) top = std::max({top, int64_t{p.x}, int64_t{p.y}, int64_t{p.z}});
  int bits = 1;
  while ((int64_t{1} << bits) <= 2 * top) ++bits;
  const int shift = std::max(0, bits - 21);
  std::vector<std::pair<uint64_t, uint32_t>> order(triangles.size());
  parallel_ranges(triangles.size(), kRange, [&](size_t first, size_t last) {
    for (size_t t = first; t < last; ++t) {
      std::array<int64_t, 3> twice_centre{};
      for (int a = 0; a < 3; ++a) {
        int64_t lo = std::numeric_limits<int64_t>::max(), hi = std::numeric_limits<int64_t>::min();
        for (uint32_t v : surface.triangles[t]) {
          const GridPoint& p = corners_[v];
          const int64_t c = a == 0 ? p.x : a == 1 ? p.y : p.z;
          lo = std::min(lo, c);
          hi = std::max(hi, c);
        }
        twice_centre[a] = lo + hi;
      }
      order[t] = {morton63(twice_centre, shift), static_cast<uint32_t>(t)};
    }
  });
  parallel_sort(order.begin(), order.end());
  triangles_.resize(triangles.size());
  parallel_ranges(triangles.size(), kRange, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) triangles_[k] = surface.triangles[order[k].second];
  });
  release(surface.triangles);
  std::vector<uint64_t> codes(order.size());
  for (size_t k = 0; k < order.size(); ++k) codes[k] = order[k].first;
  release(order);
  nodes_.reserve(triangles_.size() / 2 + 1);
  make_node(codes, 0, static_cast<uint32_t>(triangles_.size()));
  nodes_.shrink_to_fit();
}

uint32_t TriangleDistanceTree::make_node(std::span<const uint64_t> codes, uint32_t first, uint32_t last) {
  const auto at = static_cast<uint32_t>(nodes_.size());
  nodes_.emplace_back();
  std::array<float, 3> lo{kInfinityF, kInfinityF, kInfinityF}, hi{-kInfinityF, -kInfinityF, -kInfinityF};
  if (last - first <= kLeafTriangles) {
    for (uint32_t t = first; t < last; ++t)
      for (uint32_t v : triangles_[t]) {
        const GridPoint& p = corners_[v];
        const std::array<float, 3> c{static_cast<float>(p.x), static_cast<float>(p.y),
                                     static_cast<float>(p.z)};
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
      }
    nodes_[at] = {lo, hi, first, last - first};
    return at;
  }
  // Split where the highest bit in which the range's codes differ turns
  // to 1; in the middle where they are all equal.
  uint32_t split = first + (last - first) / 2;
  const uint64_t differ = codes[first] ^ codes[last - 1];
  if (differ != 0) {
    const uint64_t bit = uint64_t{1} << (63 - std::countl_zero(differ));
    split = static_cast<uint32_t>(std::partition_point(codes.begin() + first, codes.begin() + last,
                                                       [&](uint64_t c) { return !(c & bit); }) -
                                  codes.begin());
  }
  make_node(codes, first, split);
  const uint32_t right = make_node(codes, split, last);
  const Node &l = nodes_[at + 1], &r = nodes_[right];
  for (int a = 0; a < 3; ++a) lo[a] = std::min(l.lo[a], r.lo[a]), hi[a] = std::max(l.hi[a], r.hi[a]);
  nodes_[at] = {lo, hi, right, 0};
  return at;
}

size_t TriangleDistanceTree::bytes() const {
  return corners_.capacity() * sizeof(GridPoint) + triangles_.capacity() * sizeof(triangles_[0]) +
         nodes_.capacity() * sizeof(Node);
}

double TriangleDistanceTree::box_squared(const Node& node, const std::array<double, 3>& q) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double lo = node.lo[a], hi = node.hi[a];
    const double d = std::max(0.0, (q[a] < lo ? lo - q[a] : q[a] > hi ? q[a] - hi : 0.0) - kSlack);
    d2 += d * d;
  }
  return d2;
}

double TriangleDistanceTree::triangle_box_squared(size_t triangle, const std::array<double, 3>& q) const {
  const auto& t = triangles_[triangle];
  const GridPoint &a = corners_[t[0]], &b = corners_[t[1]], &c = corners_[t[2]];
  const auto axis = [&](int32_t u, int32_t v, int32_t w, double x) {
    const double lo = std::min({u, v, w}), hi = std::max({u, v, w});
    const double d = std::max(0.0, (x < lo ? lo - x : x > hi ? x - hi : 0.0) - kSlack);
    return d * d;
  };
  return axis(a.x, b.x, c.x, q[0]) + axis(a.y, b.y, c.y, q[1]) + axis(a.z, b.z, c.z, q[2]);
}

double TriangleDistanceTree::triangle_squared(size_t triangle, const std::array<double, 3>& q) const {
  const auto point = [&](uint32_t v) {
    const GridPoint& p = corners_[v];
    return K::Point_3(p.x, p.y, p.z);
  };
  const auto& t = triangles_[triangle];
  const K::Point_3 query(q[0], q[1], q[2]);
  const K::Triangle_3 tri(point(t[0]), point(t[1]), point(t[2]));
  // As CGAL's AABB tree measures it: the squared distance to the projection.
  const K::Point_3 nearest = K().construct_projected_point_3_object()(tri, query);
  return K().compute_squared_distance_3_object()(query, nearest);
}

double TriangleDistanceTree::squared_distance(const std::array<double, 3>& q) const {
  if (triangles_.empty()) return kInfinity;
  double best = kInfinity;
  // Nodes to visit with their squared distances. A path is at most 63
  // radix splits and 28 splits of equal codes deep (2^31 triangles, 8 to a
  // leaf), and the stack holds at most one node beside each of its nodes.
  struct Entry {
    uint32_t node;
    double d2;
  };
  std::array<Entry, 128> stack;
  size_t top = 0;
  stack[top++] = {0, box_squared(nodes_[0], q)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 > best) continue;
    const Node& n = nodes_[e.node];
    if (n.count > 0) {
      for (uint32_t t = n.index; t < n.index + n.count; ++t)
        if (triangle_box_squared(t, q) <= best) best = std::min(best, triangle_squared(t, q));
      continue;
    }
    const Entry a{e.node + 1, box_squared(nodes_[e.node + 1], q)},
        b{n.index, box_squared(nodes_[n.index], q)};
    // The nearer is taken first: pushed last.
    const Entry& near = a.d2 <= b.d2 ? a : b;
    const Entry& far = a.d2 <= b.d2 ? b : a;
    if (far.d2 <= best) stack[top++] = far;
    if (near.d2 <= best) stack[top++] = near;
    DTM_CHECK(top <= stack.size());
  }
  return best;
}

std::vector<double> TriangleDistanceTree::squared_distances(std::span<const GridPoint> queries) const {
  std::vector<double> squared(queries.size(), kInfinity);
  if (triangles_.empty()) return squared;
  parallel_ranges(queries.size(), kQueryRange, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) {
      const GridPoint& p = queries[i];
      squared[i] = squared_distance({double(p.x), double(p.y), double(p.z)});
    }
  });
  return squared;
}

std::vector<double> TriangleDistanceTree::squared_distances(
    std::span<const std::array<double, 3>> queries) const {
  std::vector<double> squared(queries.size(), kInfinity);
  if (triangles_.empty()) return squared;
  parallel_ranges(queries.size(), kQueryRange, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) squared[i] = squared_distance(queries[i]);
  });
  return squared;
}

}  // namespace dtm
