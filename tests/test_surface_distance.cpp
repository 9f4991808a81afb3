// The shape-error measurements: the incremental tracker (level after level)
// must give what a search from scratch gives on every surface, the fast
// boundary extraction what a plain global sort gives, and the hierarchy's
// and the reference shape's per-level errors must not depend on either.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "core/hierarchy.h"
#include "core/reference_shape.h"
#include "core/surface_distance.h"
#include "test_support.h"
#include "tools/formats/surface_writers.h"

namespace dtm {
namespace {

std::vector<GridPoint> boundary_vertices(std::span<const std::array<uint32_t, 3>> triangles,
                                         std::span<const GridPoint> points) {
  std::vector<uint32_t> ids;
  for (const auto& t : triangles) ids.insert(ids.end(), t.begin(), t.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<GridPoint> out;
  for (uint32_t v : ids) out.push_back(points[v]);
  return out;
}

void expect_same(const DistanceSummary& a, const DistanceSummary& b, const std::string& where) {
  // The same triangles, possibly given with their corners in another order:
  // equal up to the rounding of the projection.
  EXPECT_NEAR(a.max, b.max, 1e-9 * std::max(1.0, b.max)) << where;
  EXPECT_NEAR(a.mean, b.mean, 1e-9 * std::max(1.0, b.mean)) << where;
}

TEST(SurfaceDistanceTracker, EqualsAFullSearchOnEveryLevelInAnyOrder) {
  const auto points = test::load_quantized("bunny_10k").points;
  HierarchyOptions options;
  options.dmax = 128;
  options.measure_boundary_error = false;
  const Hierarchy h = build_hierarchy(points, options).value();
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
