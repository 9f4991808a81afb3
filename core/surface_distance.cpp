#include "core/surface_distance.h"

#include <CGAL/AABB_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <boost/iterator/counting_iterator.hpp>
#include <cmath>
#include <limits>
#include <optional>
#include <thread>
#include <vector>

#include "common/atomic_counts.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/release.h"
#include "common/status.h"
#include "core/aabb_on_every_core.h"
#include "core/surface_corners.h"

namespace dtm {
namespace {
using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 to_point(const GridPoint& p) { return {double(p.x), double(p.y), double(p.z)}; }

// Items per range of the loops on every core.
constexpr size_t kRange = 8192;
// How much farther than a query's nearest point the point that bounds its
// check lies (grid units; grid coordinates are below 2^24, where a
// double's rounding is under 4e-9).
constexpr double kHintMargin = 1e-6;
// Names each once, ascending.
bool strictly_ascending(std::span<const uint32_t> names) {
  return std::adjacent_find(names.begin(), names.end(), [](uint32_t a, uint32_t b) { return a >= b; }) ==
         names.end();
}

DistanceSummary no_surface() {
  const double inf = std::numeric_limits<double>::infinity();
  return {inf, inf};
}

using TriangleKey = std::array<uint32_t, 3>;  // sorted vertex ids

// A fixed surface's tree holds 4-byte triangle ids and makes each triangle
// from its corners when a query reaches it, rather than a soup of
// Triangle_3 beside the tree (72 bytes a triangle). (The reference's
// boundary, which a level built as one block holds whole, is searched by
// core/triangle_distance_tree.h, smaller still.)
using CompactSurface = SurfaceCorners;
struct TriangleById {
  using key_type = uint32_t;
  using value_type = K::Triangle_3;
  using reference = K::Triangle_3;
  using category = boost::readable_property_map_tag;
  const CompactSurface* surface = nullptr;
  friend K::Triangle_3 get(const TriangleById& m, uint32_t t) {
    const auto& c = m.surface->triangles[t];
    return {to_point(m.surface->corners[c[0]]), to_point(m.surface->corners[c[1]]),
            to_point(m.surface->corners[c[2]])};
  }
};
// A triangle's reference point: its first corner, as Triangle_3's primitive's.
struct FirstCornerById {
  using key_type = uint32_t;
  using value_type = K::Point_3;
  using reference = K::Point_3;
  using category = boost::readable_property_map_tag;
  const CompactSurface* surface = nullptr;
  friend K::Point_3 get(const FirstCornerById& m, uint32_t t) {
    return to_point(m.surface->corners[m.surface->triangles[t][0]]);
  }
};
using IdPrimitive =
    CGAL::AABB_primitive<uint32_t, TriangleById, FirstCornerById, CGAL::Tag_true, CGAL::Tag_false>;
using IdTree = CGAL::AABB_tree<CGAL::AABB_traits<K, IdPrimitive>>;
}  // namespace

DistanceSummary summarize_squared(std::span<const double> squared) {
  DistanceSummary out;
  double sum = 0;
  for (double d2 : squared) {
    const double d = std::sqrt(d2);
    out.max = std::max(out.max, d);
    sum += d;
  }
  out.mean = squared.empty() ? 0 : sum / squared.size();
  return out;
}

struct FixedSurface::State {
  CompactSurface surface;  // the tree's property maps point here (State does not move)
  std::optional<IdTree> tree;
  std::optional<DistanceHints<IdTree>> hints;  // the queries' first guesses
  IdTree::Point_and_primitive_id hint(const K::Point_3& q) const { return hints->nearest(q); }
};

FixedSurface::FixedSurface(std::span<const GridPoint> vertices,
                           std::span<const std::array<uint32_t, 3>> triangles)
    : state_(std::make_unique<State>()) {
  if (triangles.empty()) return;
  // (On every core: a block's surface has some 10^5 triangles.)
  state_->surface = surface_corners(vertices, triangles);
  const CompactSurface& s = state_->surface;
  const auto count = static_cast<uint32_t>(s.triangles.size());
  state_->tree.emplace(boost::counting_iterator<uint32_t>(0), boost::counting_iterator<uint32_t>(count),
                       TriangleById{&s}, FirstCornerById{&s});
  // Each triangle's reference point is its first corner (FirstCornerById).
  std::vector<IdTree::Point_and_primitive_id> references(count);
  parallel_ranges(count, kRange, [&](size_t first, size_t last) {
    for (size_t t = first; t < last; ++t)
      references[t] = {to_point(s.corners[s.triangles[t][0]]), static_cast<uint32_t>(t)};
  });
  state_->hints.emplace(references);
  build_on_every_core(*state_->tree);
}
FixedSurface::~FixedSurface() = default;
FixedSurface::FixedSurface(FixedSurface&&) noexcept = default;
FixedSurface& FixedSurface::operator=(FixedSurface&&) noexcept = default;

std::vector<double> FixedSurface::squared_distances(std::span<const GridPoint> queries) const {
  std::vector<double> squared(queries.size(), std::numeric_limits<double>::infinity());
  if (!state_->tree) return squared;
  const IdTree& tree = *state_->tree;
  parallel_for(queries.size(), [&](size_t i) {
    const K::Point_3 q = to_point(queries[i]);
    squared[i] = tree.squared_distance(q, state_->hint(q).first);
  });
  return squared;
}

std::vector<double> FixedSurface::squared_distances(std::span<const std::array<double, 3>> queries) const {
  std::vector<double> squared(queries.size(), std::numeric_limits<double>::infinity());
  if (!state_->tree) return squared;
  const IdTree& tree = *state_->tree;
  parallel_for(queries.size(), [&](size_t i) {
    const K::Point_3 q(queries[i][0], queries[i][1], queries[i][2]);
    squared[i] = tree.squared_distance(q, state_->hint(q).first);
  });
  return squared;
}

std::vector<uint32_t> FixedSurface::nearest_triangles(std::span<const std::array<double, 3>> queries) const {
  if (!state_->tree) return {};
  std::vector<uint32_t> nearest(queries.size());
  const IdTree& tree = *state_->tree;
  parallel_for(queries.size(), [&](size_t i) {
    const K::Point_3 q(queries[i][0], queries[i][1], queries[i][2]);
    nearest[i] = tree.closest_point_and_primitive(q, state_->hint(q)).second;
  });
  return nearest;
}

double FixedSurface::squared_distance(const GridPoint& query) const {
  if (!state_->tree) return std::numeric_limits<double>::infinity();
  const K::Point_3 q = to_point(query);
  return state_->tree->squared_distance(q, state_->hint(q).first);
}

DistanceSummary distance_to_surface(std::span<const GridPoint> vertices,
                                    std::span<const std::array<uint32_t, 3>> triangles,
                                    std::span<const GridPoint> queries) {
  if (queries.empty()) return {};
  if (triangles.empty()) return no_surface();
  return summarize_squared(FixedSurface(vertices, triangles).squared_distances(queries));
}

struct SurfaceDistanceTracker::State {
  std::span<const GridPoint> queries;  // the caller's
  K::Point_3 query(size_t q) const { return to_point(queries[q]); }
  // Per query, after a measure(): the squared distance and the key of the
  // triangle nearest it (not the nearest point: 24 bytes a query, 16 MiB
  // for a reference boundary of 698k vertices; a check needs only a point
  // a little farther, measure() says why).
  std::vector<double> squared;
  std::vector<TriangleKey> nearest_triangle;
  bool measured = false;
  std::vector<TriangleKey> previous;    // the last surface's keys, sorted
  std::span<const uint32_t> query_ids;  // the caller's; empty: queries have no names
  size_t names = 0;                     // the largest name + 1
  bool ids_ascending = false;           // query_ids are, each once
};

SurfaceDistanceTracker::SurfaceDistanceTracker(std::span<const GridPoint> queries,
                                               std::span<const uint32_t> query_ids)
    : state_(std::make_unique<State>()) {
  DTM_CHECK(query_ids.empty() || query_ids.size() == queries.size());
  state_->query_ids = query_ids;
  if (!query_ids.empty()) state_->names = size_t{*std::max_element(query_ids.begin(), query_ids.end())} + 1;
  state_->ids_ascending = strictly_ascending(query_ids);
  state_->queries = queries;
  state_->squared.resize(queries.size());
  state_->nearest_triangle.resize(queries.size());
}
SurfaceDistanceTracker::~SurfaceDistanceTracker() = default;
SurfaceDistanceTracker::SurfaceDistanceTracker(SurfaceDistanceTracker&&) noexcept = default;
SurfaceDistanceTracker& SurfaceDistanceTracker::operator=(SurfaceDistanceTracker&&) noexcept = default;

DistanceSummary SurfaceDistanceTracker::measure(std::span<const GridPoint> vertices,
                                                std::span<const uint32_t> ids,
                                                std::span<const std::array<uint32_t, 3>> triangles) {
  State& s = *state_;
  if (s.queries.empty()) return {};
  if (triangles.empty()) {
    s.measured = false;
    s.previous.clear();
    std::fill(s.squared.begin(), s.squared.end(), std::numeric_limits<double>::infinity());
    return no_surface();
  }
  // Per triangle, its key and whether the previous surface had it; per
  // query, whether it is a vertex of this surface (the first triangle that
  // has it) and else whether its nearest triangle is still there: on every
  // core, the lists built from them in order.
  const size_t n = triangles.size();
  std::vector<Triangle> soup(n);
  std::vector<TriangleKey> keys(n);
  std::vector<uint8_t> is_added(n);
  parallel_ranges(n, kRange, [&](size_t first, size_t last) {
    for (size_t i = first; i < last; ++i) {
      const auto& t = triangles[i];
      soup[i] = Triangle(to_point(vertices[t[0]]), to_point(vertices[t[1]]), to_point(vertices[t[2]]));
      TriangleKey k = ids.empty() ? t : TriangleKey{ids[t[0]], ids[t[1]], ids[t[2]]};
      std::sort(k.begin(), k.end());
      keys[i] = k;
      is_added[i] = !s.measured || !std::binary_search(s.previous.begin(), s.previous.end(), k);
    }
  });
  std::vector<TriangleKey> sorted_keys = keys;
  parallel_sort(sorted_keys.begin(), sorted_keys.end());  // distinct keys

  // The triangles this surface adds to the previous one.
  const std::vector<uint32_t> added_index =
      collect_in_order<uint32_t>(n, kRange, [&](size_t first, size_t last, std::vector<uint32_t>& out) {
        for (size_t i = first; i < last; ++i)
          if (is_added[i]) out.push_back(static_cast<uint32_t>(i));
      });
  std::vector<Triangle> added(added_index.size());
  for (size_t j = 0; j < added.size(); ++j) added[j] = soup[added_index[j]];
  // A named query that is a vertex of the surface is on it. The other
  // queries whose nearest triangle is gone are searched in full, the rest
  // against the added triangles only.
  constexpr uint32_t kNone = UINT32_MAX;
  // Per named query, the first triangle it is a corner of: the least, on
  // every core (an atomic minimum; the loop in order was serial). When the
  // vertices' names and the queries' both ascend (each once), each vertex's query is
  // found by one merge of the two and the minimum is kept per query; else
  // it is kept per name, in an array as long as the largest name (a
  // bricked level built in one block is measured against the whole
  // reference boundary, whose names reach the largest grid id: 38 MiB at
  // bunny_10m, for its 698k queries).
  std::vector<uint32_t> first_triangle;
  const bool merged = !s.query_ids.empty() && s.ids_ascending && !ids.empty() && strictly_ascending(ids);
  if (merged) {
    std::vector<uint32_t> query_of(vertices.size(), kNone);
    for (size_t v = 0, q = 0; v < ids.size() && q < s.query_ids.size();) {
      if (ids[v] < s.query_ids[q])
        ++v;
      else if (s.query_ids[q] < ids[v])
        ++q;
      else
        query_of[v++] = static_cast<uint32_t>(q++);
    }
    first_triangle.assign(s.query_ids.size(), kNone);
    parallel_ranges(n, kRange, [&](size_t first, size_t last) {
      for (size_t i = first; i < last; ++i)
        for (uint32_t v : triangles[i])
          if (query_of[v] != kNone) atomic_store_min(first_triangle[query_of[v]], static_cast<uint32_t>(i));
    });
  } else if (!s.query_ids.empty()) {
    first_triangle.assign(s.names, kNone);
    parallel_ranges(n, kRange, [&](size_t first, size_t last) {
      for (size_t i = first; i < last; ++i)
        for (uint32_t v : triangles[i]) {
          const uint32_t name = ids.empty() ? v : ids[v];
          if (name >= s.names) continue;
          atomic_store_min(first_triangle[name], static_cast<uint32_t>(i));
        }
    });
  }
  enum : uint8_t { kOnSurface, kCheck, kFull };
  std::vector<uint8_t> kind(s.queries.size());
  parallel_ranges(s.queries.size(), kRange, [&](size_t first, size_t last) {
    for (size_t q = first; q < last; ++q) {
      const uint32_t at = s.query_ids.empty() ? kNone : first_triangle[merged ? q : s.query_ids[q]];
      if (at != kNone) {
        s.squared[q] = 0;
        s.nearest_triangle[q] = keys[at];
        kind[q] = kOnSurface;
      } else {
        kind[q] =
            s.measured && std::binary_search(sorted_keys.begin(), sorted_keys.end(), s.nearest_triangle[q])
                ? kCheck
                : kFull;
      }
    }
  });
  const auto queries_of = [&](uint8_t wanted) {
    return collect_in_order<uint32_t>(s.queries.size(), kRange,
                                      [&](size_t first, size_t last, std::vector<uint32_t>& out) {
                                        for (size_t q = first; q < last; ++q)
                                          if (kind[q] == wanted) out.push_back(static_cast<uint32_t>(q));
                                      });
  };
  const std::vector<uint32_t> full = queries_of(kFull), check = queries_of(kCheck);

  if (!full.empty()) {
    Tree tree(soup.cbegin(), soup.cend());
    // A triangle's reference point is its first corner (AABB_triangle_primitive).
    std::vector<Tree::Point_and_primitive_id> references(n);
    parallel_ranges(n, kRange, [&](size_t first, size_t last) {
      for (size_t i = first; i < last; ++i)
        references[i] = {soup[i].vertex(0), soup.cbegin() + static_cast<std::ptrdiff_t>(i)};
    });
    const DistanceHints<Tree> hints(references);
    release(references);
    build_on_every_core(tree);
    parallel_for(full.size(), [&](size_t j) {
      const uint32_t q = full[j];
      const K::Point_3 p = s.query(q);
      const auto hit = tree.closest_point_and_primitive(p, hints.nearest(p));
      s.squared[q] = CGAL::squared_distance(p, hit.first);
      s.nearest_triangle[q] = keys[static_cast<size_t>(hit.second - soup.cbegin())];
    });
  }
  if (!check.empty() && !added.empty()) {
    Tree tree(added.cbegin(), added.cend());
    build_on_every_core(tree);
    parallel_for(check.size(), [&](size_t j) {
      const uint32_t q = check[j];
      // A point a little farther than the nearest one bounds the search
      // (kHintMargin past it, far more than its rounding): the traversal
      // returns it unless an added triangle is nearer than it, and only one
      // nearer than the nearest point counts, as when the nearest point
      // itself bounded the search (a corner of the nearest triangle would
      // not: CGAL's projection onto a vertex can round a few ulps past the
      // vertex, which an added triangle at that vertex then ties).
      const K::Point_3 p = s.query(q);
      const K::Point_3 bound(p.x() + std::sqrt(s.squared[q]) + kHintMargin, p.y(), p.z());
      const auto hit = tree.closest_point_and_primitive(p, {bound, added.cbegin()});
      if (hit.first == bound) return;
      const double d2 = CGAL::squared_distance(p, hit.first);
      if (d2 < s.squared[q]) {
        s.squared[q] = d2;
        s.nearest_triangle[q] = keys[added_index[static_cast<size_t>(hit.second - added.cbegin())]];
      }
    });
  }
  s.measured = true;
  s.previous = std::move(sorted_keys);
  return summarize_squared(s.squared);
}

std::vector<double> SurfaceDistanceTracker::squared() const { return state_->squared; }
std::vector<std::array<uint32_t, 3>> SurfaceDistanceTracker::nearest_triangles() const {
  return state_->nearest_triangle;
}
std::array<uint32_t, 3> SurfaceDistanceTracker::nearest_triangle(size_t query) const {
  return state_->nearest_triangle[query];
}

}  // namespace dtm
