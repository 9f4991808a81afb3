// The shape-error measurements: the incremental tracker (level after level)
// must give what a search from scratch gives on every surface, the fast
// boundary extraction what a plain global sort gives, and the hierarchy's
// and the reference shape's per-level errors must not depend on either.
#include <CGAL/Simple_cartesian.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>

#include "core/hierarchy.h"
#include "core/reference_shape.h"
#include "core/surface_distance.h"
#include "core/triangle_distance_tree.h"
#include "mesh/topology.h"
#include "test_support.h"
#include "tools/formats/surface_writers.h"
#include "tools/formats/tetgen.h"

namespace dtm {
namespace {

// The triangles' corners, ascending, each once.
std::vector<uint32_t> corner_ids(std::span<const std::array<uint32_t, 3>> triangles) {
  std::vector<uint32_t> ids;
  for (const auto& t : triangles) ids.insert(ids.end(), t.begin(), t.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

std::vector<GridPoint> boundary_vertices(std::span<const std::array<uint32_t, 3>> triangles,
                                         std::span<const GridPoint> points) {
  std::vector<GridPoint> out;
  for (uint32_t v : corner_ids(triangles)) out.push_back(points[v]);
  return out;
}

// bunny_10k's paper hierarchy with a loose D_max: many levels, each
// surface straying farther from level 0's.
Hierarchy many_levels(std::span<const GridPoint> points) {
  HierarchyOptions options;
  options.dmax = 128;
  options.measure_boundary_error = false;
  return build_hierarchy(points, options).value();
}

void expect_same(const DistanceSummary& a, const DistanceSummary& b, const std::string& where) {
  // The same triangles, possibly given with their corners in another order:
  // equal up to the rounding of the projection.
  EXPECT_NEAR(a.max, b.max, 1e-9 * std::max(1.0, b.max)) << where;
  EXPECT_NEAR(a.mean, b.mean, 1e-9 * std::max(1.0, b.mean)) << where;
}

TEST(SurfaceDistanceTracker, EqualsAFullSearchOnEveryLevelInAnyOrder) {
  const auto points = test::load_quantized("bunny_10k").points;
  const Hierarchy h = many_levels(points);
  ASSERT_GE(h.levels.size(), 10u);
  std::vector<std::vector<std::array<uint32_t, 3>>> surfaces;
  for (const Level& level : h.levels) surfaces.push_back(boundary_triangles(level.carved_cells()));
  const std::vector<GridPoint> queries = boundary_vertices(surfaces[0], points);

  // Fine to coarse (as the hierarchy measures), then jumping about, with an
  // empty surface in between (which forgets everything).
  std::vector<size_t> order;
  for (size_t l = 0; l < surfaces.size(); ++l) order.push_back(l);
  for (size_t l : {5, 1, 9, 0, 9, 3}) order.push_back(l);
  SurfaceDistanceTracker tracker(queries);
  for (size_t step = 0; step < order.size(); ++step) {
    const size_t l = order[step];
    expect_same(tracker.measure(points, {}, surfaces[l]), distance_to_surface(points, surfaces[l], queries),
                "level " + std::to_string(l) + ", step " + std::to_string(step));
    if (step == surfaces.size() + 2) {
      EXPECT_TRUE(std::isinf(tracker.measure(points, {}, {}).max));
    }
  }
  // The measurement is not trivial: the coarsest surface strays.
  EXPECT_GT(distance_to_surface(points, surfaces.back(), queries).max, 0.0);
}

TEST(SurfaceDistanceTracker, NamesMakeTrianglesTheSameAcrossRenumbering) {
  // The hierarchy gives each level's vertices local numbers and their grid
  // ids as names: renumbering between calls must not confuse the tracker.
  const auto points = test::load_quantized("torus_288").points;
  const Hierarchy h = build_hierarchy(points, {}).value();
  ASSERT_GE(h.levels.size(), 2u);
  const auto fine = boundary_triangles(h.levels[0].carved_cells());
  const std::vector<GridPoint> queries = boundary_vertices(fine, points);
  SurfaceDistanceTracker tracker(queries);
  for (size_t l = 0; l < h.levels.size(); ++l) {
    const Level& level = h.levels[l];
    std::map<uint32_t, uint32_t> local;
    std::vector<GridPoint> level_points;
    for (uint32_t id : level.vertices) {
      local[id] = static_cast<uint32_t>(level_points.size());
      level_points.push_back(points[id]);
    }
    std::vector<std::array<uint32_t, 3>> renumbered;
    for (const auto& t : boundary_triangles(level.carved_cells()))
      renumbered.push_back({local[t[0]], local[t[1]], local[t[2]]});
    expect_same(tracker.measure(level_points, level.vertices, renumbered),
                distance_to_surface(level_points, renumbered, queries), "level " + std::to_string(l));
  }
}

// Named queries (a reference's boundary vertices by grid id): a query that
// is a vertex of the surface is at 0, found by merging the names when the
// surface's names ascend as the queries' do, and by name otherwise; both
// give the same doubles and nearest triangles, and a full search's figures.
TEST(SurfaceDistanceTracker, NamedQueriesAreTheSameWhetherTheSurfacesNamesAscendOrNot) {
  const auto points = test::load_quantized("bunny_10k").points;
  const Hierarchy h = many_levels(points);
  ASSERT_GE(h.levels.size(), 4u);
  const std::vector<uint32_t> query_ids = corner_ids(boundary_triangles(h.levels[0].carved_cells()));
  std::vector<GridPoint> queries;
  for (uint32_t id : query_ids) queries.push_back(points[id]);
  SurfaceDistanceTracker ascending(queries, query_ids), shuffled(queries, query_ids);
  std::mt19937 random(7);
  for (size_t l = 0; l < h.levels.size(); ++l) {
    const Level& level = h.levels[l];
    const auto surface = boundary_triangles(level.carved_cells());
    // The level's vertices by ascending grid id, then the same in a random order.
    std::vector<uint32_t> ids = level.vertices;
    std::sort(ids.begin(), ids.end());
    std::vector<uint32_t> order(ids.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), random);
    std::map<uint32_t, uint32_t> at_sorted, at_shuffled;
    std::vector<GridPoint> sorted_points, shuffled_points;
    std::vector<uint32_t> shuffled_ids;
    for (uint32_t i = 0; i < ids.size(); ++i) {
      at_sorted[ids[i]] = i;
      sorted_points.push_back(points[ids[i]]);
      at_shuffled[ids[order[i]]] = i;
      shuffled_points.push_back(points[ids[order[i]]]);
      shuffled_ids.push_back(ids[order[i]]);
    }
    std::vector<std::array<uint32_t, 3>> by_sorted, by_shuffled;
    for (const auto& t : surface) {
      by_sorted.push_back({at_sorted[t[0]], at_sorted[t[1]], at_sorted[t[2]]});
      by_shuffled.push_back({at_shuffled[t[0]], at_shuffled[t[1]], at_shuffled[t[2]]});
    }
    const std::string where = "level " + std::to_string(l);
    const DistanceSummary a = ascending.measure(sorted_points, ids, by_sorted);
    const DistanceSummary b = shuffled.measure(shuffled_points, shuffled_ids, by_shuffled);
    EXPECT_EQ(ascending.squared(), shuffled.squared()) << where;
    EXPECT_EQ(ascending.nearest_triangles(), shuffled.nearest_triangles()) << where;
    // Level after level, each distance is the double a search from
    // scratch finds (checks against the added triangles only, bounded by a
    // point beyond the nearest: nothing nearer is missed, nothing farther
    // taken).
    SurfaceDistanceTracker fresh(queries, query_ids);
    fresh.measure(sorted_points, ids, by_sorted);
    EXPECT_EQ(ascending.squared(), fresh.squared()) << where;
    expect_same(a, distance_to_surface(points, surface, queries), where);
    expect_same(b, a, where);
    // The queries on the level's surface are at 0, the others not.
    const std::vector<double> squared = ascending.squared();
    const std::vector<uint32_t> on_surface = corner_ids(surface);
    for (size_t q = 0; q < query_ids.size(); ++q) {
      if (std::binary_search(on_surface.begin(), on_surface.end(), query_ids[q])) {
        EXPECT_EQ(squared[q], 0.0) << where;
      }
    }
  }
}

TEST(SurfaceDistanceTracker, HierarchyErrorsAreTheFullSearchs) {
  const auto points = test::load_quantized("bunny_10k").points;
  HierarchyOptions options;
  options.dmax = 128;
  const Hierarchy h = build_hierarchy(points, options).value();
  const std::vector<GridPoint> originals =
      boundary_vertices(boundary_triangles(h.levels[0].carved_cells()), points);
  for (const Level& level : h.levels) {
    const DistanceSummary d =
        distance_to_surface(points, boundary_triangles(level.carved_cells()), originals);
    EXPECT_NEAR(level.stats.max_boundary_error, d.max, 1e-9 * std::max(1.0, d.max)) << level.stats.level;
    EXPECT_NEAR(level.stats.mean_boundary_error, d.mean, 1e-9 * std::max(1.0, d.mean)) << level.stats.level;
  }
  EXPECT_GT(h.levels.back().stats.max_boundary_error, 0.0);
}

// The least squared distance from x to the triangles, each measured as
// CGAL's AABB tree measures it (to CGAL's projection onto the triangle).
double nearest_of_every_triangle(std::span<const GridPoint> points,
                                 std::span<const std::array<uint32_t, 3>> triangles,
                                 const std::array<double, 3>& x) {
  using K = CGAL::Simple_cartesian<double>;
  const K::Point_3 query(x[0], x[1], x[2]);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : triangles) {
    const auto at = [&](uint32_t v) { return K::Point_3(points[v].x, points[v].y, points[v].z); };
    const K::Triangle_3 tri(at(t[0]), at(t[1]), at(t[2]));
    best =
        std::min(best, CGAL::squared_distance(query, K().construct_projected_point_3_object()(tri, query)));
  }
  return best;
}

// The compact tree's distances (a reference's boundary, held whole by many
// ranks) against every triangle tried: the same doubles, bit for bit,
// whatever order the triangles come in; and within rounding of CGAL's AABB
// tree's (FixedSurface), which the shape measure used before.
TEST(TriangleDistanceTree, IsTheLeastOverEveryTriangleInAnyOrder) {
  const auto q = test::load_quantized("bunny_10k");
  const NodeFile node = read_tetgen_node(test::data_path("bunny_10k.node"));
  auto tets = read_tetgen_ele(test::data_path("bunny_10k.ele"), node.points.size(), node.index_base);
  grid_tetrahedra_in_place(tets, q);
  const std::vector<std::array<uint32_t, 3>> surface = boundary_triangles(tets);
  ASSERT_GT(surface.size(), 3000u);
  // Queries: the surface's own corners (at 0), grid points all over the
  // box and beyond it, and points between grid points.
  std::vector<std::array<double, 3>> queries;
  for (size_t t = 0; t < surface.size(); t += 7) {
    const GridPoint& p = q.points[surface[t][0]];
    queries.push_back({double(p.x), double(p.y), double(p.z)});
  }
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> anywhere(-2000, 18384);
  std::uniform_int_distribution<int> grid(-500, 16884);
  for (int i = 0; i < 1500; ++i) {
    queries.push_back({anywhere(rng), anywhere(rng), anywhere(rng)});
    queries.push_back({double(grid(rng)), double(grid(rng)), double(grid(rng))});
  }
  const auto every_triangle = [&](const std::array<double, 3>& x) {
    return nearest_of_every_triangle(q.points, surface, x);
  };
  const TriangleDistanceTree tree(q.points, surface);
  EXPECT_EQ(tree.triangles(), surface.size());
  EXPECT_LT(tree.bytes(), 40 * surface.size());
  std::vector<std::array<uint32_t, 3>> shuffled = surface;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const TriangleDistanceTree other(q.points, shuffled);
  const std::vector<double> found = tree.squared_distances(queries), again = other.squared_distances(queries);
  const std::vector<double> cgal = FixedSurface(q.points, surface).squared_distances(queries);
  size_t zero = 0, same_as_cgal = 0;
  for (size_t i = 0; i < queries.size(); ++i) {
    const double expected = every_triangle(queries[i]);
    ASSERT_EQ(found[i], expected) << "query " << i;
    ASSERT_EQ(again[i], expected) << "query " << i;
    EXPECT_EQ(tree.squared_distance(queries[i]), expected);
    EXPECT_NEAR(cgal[i], expected, 1e-12 * std::max(1.0, expected)) << "query " << i;
    zero += expected == 0;
    same_as_cgal += cgal[i] == expected;
  }
  EXPECT_GE(zero, surface.size() / 7);
  EXPECT_GE(same_as_cgal, queries.size() * 99 / 100);
  // Grid points: the same as their doubles.
  std::vector<GridPoint> on_grid;
  for (int i = 0; i < 200; ++i) on_grid.push_back({grid(rng), grid(rng), grid(rng)});
  const std::vector<double> grid_found = tree.squared_distances(on_grid);
  for (size_t i = 0; i < on_grid.size(); ++i)
    EXPECT_EQ(grid_found[i],
              every_triangle({double(on_grid[i].x), double(on_grid[i].y), double(on_grid[i].z)}));
  // No triangle: infinitely far.
  EXPECT_TRUE(std::isinf(TriangleDistanceTree(q.points, {}).squared_distances(on_grid).at(0)));
  // A part of the surface holding a query's nearest triangle (as a block's
  // region holds it) gives the whole's double.
  std::vector<std::array<uint32_t, 3>> part;
  for (const auto& t : surface)
    if (q.points[t[0]].x < 8192) part.push_back(t);
  const TriangleDistanceTree of_part(q.points, part);
  size_t in_part = 0;
  for (size_t i = 0; i < queries.size(); ++i) {
    if (nearest_of_every_triangle(q.points, part, queries[i]) != found[i]) continue;
    ++in_part;
    EXPECT_EQ(of_part.squared_distance(queries[i]), found[i]) << "query " << i;
  }
  EXPECT_GE(in_part, queries.size() / 4);
}

// Triangles in planes x = c and z = c, and queries a third of a unit apart
// over their edges and corners: CGAL's projection onto such a triangle may
// round the plane's coordinate toward the query, below the distance to the
// triangle's box. Nothing that could be the least is skipped.
TEST(TriangleDistanceTree, KeepsTrianglesInAxisPlanesAsEveryTriangleDoes) {
  std::vector<GridPoint> points;
  std::vector<std::array<uint32_t, 3>> triangles;
  // Rows and columns unevenly spaced, so that the triangles' normals (and
  // so the projection's rounding) differ from one to the next.
  constexpr int kSide = 24;
  const auto at = [](int32_t i) { return i * (i + 3) / 2 + 1; };
  const auto tile = [&](bool vertical, int32_t c) {
    const auto first = static_cast<uint32_t>(points.size());
    for (int32_t i = 0; i <= kSide; ++i)
      for (int32_t j = 0; j <= kSide; ++j)
        points.push_back(vertical ? GridPoint{c, at(i), at(j)} : GridPoint{at(i), at(j), c});
    for (uint32_t i = 0; i < kSide; ++i)
      for (uint32_t j = 0; j < kSide; ++j) {
        const uint32_t a = first + i * (kSide + 1) + j, b = a + 1, d = a + kSide + 1, e = d + 1;
        if ((i + j) % 2 == 0) {
          triangles.push_back({a, b, e});
          triangles.push_back({a, e, d});
        } else {
          triangles.push_back({a, b, d});
          triangles.push_back({b, e, d});
        }
      }
  };
  tile(false, 37);
  tile(true, 41);
  tile(false, 1001);
  // Over the triangles' shared edges and corners (a row or column of the
  // tiling), a third of a unit from anything else.
  std::vector<std::array<double, 3>> queries;
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> line(0, kSide), thirds(-30, 3 * at(kSide) + 30);
  for (int i = 0; i < 20000; ++i) {
    const double u = at(line(rng)), v = thirds(rng) / 3.0, w = thirds(rng) / 3.0;
    if (i % 3 == 0) queries.push_back({u, v, w});
    if (i % 3 == 1) queries.push_back({v, u, w});
    if (i % 3 == 2) queries.push_back({v, w, u});
  }
  const TriangleDistanceTree tree(points, triangles);
  std::vector<std::array<uint32_t, 3>> reversed(triangles.rbegin(), triangles.rend());
  const TriangleDistanceTree other(points, reversed);
  for (size_t i = 0; i < queries.size(); ++i) {
    const double expected = nearest_of_every_triangle(points, triangles, queries[i]);
    ASSERT_EQ(tree.squared_distance(queries[i]), expected) << "query " << i;
    ASSERT_EQ(other.squared_distance(queries[i]), expected) << "query " << i;
  }
}

TEST(ReferenceShape, RemembersNothingThatChangesItsAnswers) {
  // Measuring levels one after the other (the shape keeps what it measured)
  // equals a fresh shape per level.
  const auto q = test::load_quantized("bunny_10k");
  HierarchyOptions options;
  options.dmax = 128;
  options.measure_boundary_error = false;
  const Hierarchy h = build_hierarchy(q.points, options).value();
  // The finest level's own cells as the reference.
  ReferenceShape running(q.points, h.levels[0].carved_cells());
  for (size_t l : {size_t{0}, size_t{1}, size_t{4}, size_t{2}, h.levels.size() - 1}) {
    ReferenceShape fresh(q.points, h.levels[0].carved_cells());
    expect_same(running.distance(h.levels[l].carved_cells(), q.points).both,
                fresh.distance(h.levels[l].carved_cells(), q.points).both, "level " + std::to_string(l));
  }
  EXPECT_LE(running.distance(h.levels[0].carved_cells(), q.points).both.max, 1e-9);
}

// boundary_triangles against the plain definition: the faces that exactly
// one cell has, in ascending sorted-key order, oriented as that cell gives
// them, in one pass and in several.
TEST(BoundaryTriangles, MatchesAGlobalSort) {
  std::mt19937 rng(7);
  for (int round = 0; round < 20; ++round) {
    const uint32_t vertices = 5 + rng() % 40;
    std::vector<std::array<uint32_t, 4>> cells;
    const int count = 1 + static_cast<int>(rng() % 60);
    for (int i = 0; i < count; ++i) {
      std::array<uint32_t, 4> c;
      do {
        for (auto& v : c) v = rng() % vertices;
        auto s = c;
        std::sort(s.begin(), s.end());
        if (std::adjacent_find(s.begin(), s.end()) == s.end()) break;
      } while (true);
      cells.push_back(c);
    }
    // Repeat some cells so that shared faces occur.
    for (int i = 0; i < count / 3; ++i) {
      auto c = cells[rng() % cells.size()];
      std::swap(c[0], c[1]);
      cells.push_back(c);
    }
    static constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    std::map<std::array<uint32_t, 3>, std::vector<std::array<uint32_t, 3>>> by_key;
    for (const auto& t : cells)
      for (const auto& f : kFaces) {
        std::array<uint32_t, 3> oriented = {t[f[0]], t[f[1]], t[f[2]]}, key = oriented;
        std::sort(key.begin(), key.end());
        by_key[key].push_back(oriented);
      }
    std::vector<std::array<uint32_t, 3>> expected;
    for (const auto& [key, sides] : by_key)
      if (sides.size() == 1) expected.push_back(sides[0]);
    EXPECT_EQ(boundary_triangles(cells), expected) << "round " << round;
    // In passes over ranges of vertices (a bucket larger than a pass is a
    // pass of its own): the same faces in the same order.
    for (const size_t per_pass : {1, 7, 50})
      EXPECT_EQ(boundary_triangles(cells, per_pass), expected) << "round " << round << ", " << per_pass;
  }
  EXPECT_TRUE(boundary_triangles({}).empty());
}

}  // namespace
}  // namespace dtm
