// Properties of the hierarchy (docs/ARCHITECTURE.md §3.5-3.7): nesting, independence of
// every removed set, preservation of untouched cells, importance order,
// stopping rules, and that a decoder inserting the layers rebuilds each level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <tuple>

#include "core/boundary_simplification.h"
#include "core/coarsening.h"
#include "core/hierarchy.h"
#include "core/importance.h"
#include "mesh/geometry.h"
#include "test_support.h"

namespace dtm {
namespace {

struct Case {
  std::string name;
  std::vector<GridPoint> points;
  HierarchyOptions options;
};

HierarchyOptions dmax(double d) {
  HierarchyOptions o;
  o.dmax = d;
  return o;
}

// Each case is built once and shared by the tests below.
const std::vector<Case>& cases() {
  static const std::vector<Case> all = [] {
    std::vector<Case> c;
    // bunny_10k at q=14 in a 256-unit box with Dmax=2: 2 * 16383/256 = 128 grid units.
    c.push_back({"bunny_10k", test::load_quantized("bunny_10k").points, dmax(128)});
    c.push_back({"torus_288", test::load_quantized("torus_288").points, dmax(335)});
    c.push_back({"torus_288_grid", test::load_quantized("torus_288_grid").points, dmax(335)});
    c.push_back({"random_5bit", test::random_grid_points(2500, 5, 21), dmax(1.0)});
    HierarchyOptions grid = dmax(0.5);
    grid.stop_when_boundary_is_final = false;
    c.push_back({"full_grid_10", test::full_grid(10), grid});
    HierarchyOptions guarded = dmax(128);
    guarded.quality_guard = 0.2;
    c.push_back({"bunny_10k_guarded", test::load_quantized("bunny_10k").points, guarded});
    return c;
  }();
  return all;
}

const Hierarchy& hierarchy_of(const Case& c) {
  static std::map<std::string, Hierarchy> built;
  auto it = built.find(c.name);
  if (it == built.end()) it = built.emplace(c.name, build_hierarchy(c.points, c.options).value()).first;
  return it->second;
}

std::vector<GridPoint> gather(const std::vector<GridPoint>& pts, const std::vector<uint32_t>& ids) {
  std::vector<GridPoint> out;
  for (uint32_t i : ids) out.push_back(pts[i]);
  return out;
}

class HierarchyProperties : public ::testing::TestWithParam<size_t> {
 protected:
  const Case& c() const { return cases()[GetParam()]; }
  const Hierarchy& h() const { return hierarchy_of(c()); }
};

TEST_P(HierarchyProperties, BuildsSeveralLevels) {
  EXPECT_GE(h().levels.size(), 3u) << c().name;
  EXPECT_EQ(h().levels[0].vertices.size(), c().points.size());
}

TEST_P(HierarchyProperties, LevelsAreNested) {
  for (size_t l = 0; l + 1 < h().levels.size(); ++l) {
    const auto& fine = h().levels[l].vertices;
    const auto& coarse = h().levels[l + 1].vertices;
    ASSERT_TRUE(std::is_sorted(fine.begin(), fine.end()));
    EXPECT_LT(coarse.size(), fine.size());
    EXPECT_TRUE(std::includes(fine.begin(), fine.end(), coarse.begin(), coarse.end()))
        << "level " << l + 1 << " is not a subset of level " << l;
  }
}

TEST_P(HierarchyProperties, RemovedSetsAreIndependentAndUntouchedCellsSurvive) {
  for (size_t l = 0; l + 1 < h().levels.size(); ++l) {
    const auto& fine = h().levels[l].vertices;
    const auto& coarse = h().levels[l + 1].vertices;
    std::vector<uint8_t> removed(c().points.size(), 0);
    for (uint32_t v : fine) removed[v] = 1;
    for (uint32_t v : coarse) removed[v] = 0;

    const auto fine_pts = gather(c().points, fine), coarse_pts = gather(c().points, coarse);
    const TetMesh fine_dt = delaunay_tetrahedralize(fine_pts).value();
    for (const auto& cell : fine_dt.cells)
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
          ASSERT_FALSE(removed[fine[cell[i]]] && removed[fine[cell[j]]])
              << c().name << " level " << l << ": removed vertices " << fine[cell[i]] << " and "
              << fine[cell[j]] << " share an edge";

    const auto coarse_cells = test::cells_by_coords(delaunay_tetrahedralize(coarse_pts).value(), coarse_pts);
    size_t untouched = 0;
    for (const auto& cell : fine_dt.cells) {
      if (removed[fine[cell[0]]] || removed[fine[cell[1]]] || removed[fine[cell[2]]] ||
          removed[fine[cell[3]]])
        continue;
      ++untouched;
      test::CellByCoords t = {fine_pts[cell[0]], fine_pts[cell[1]], fine_pts[cell[2]], fine_pts[cell[3]]};
      std::sort(t.begin(), t.end());
      ASSERT_TRUE(std::binary_search(coarse_cells.begin(), coarse_cells.end(), t))
          << c().name << " level " << l << ": an untouched cell is missing at level " << l + 1;
    }
    EXPECT_GT(untouched, 0u);
  }
}

TEST_P(HierarchyProperties, EachLevelIsTheCarvedDelaunayOfItsVertices) {
  for (const Level& level : h().levels) {
    const auto pts = gather(c().points, level.vertices);
    const LevelGeometry L = analyze_level(pts, c().options.alpha).value();
    EXPECT_DOUBLE_EQ(L.alpha, level.alpha);
    std::vector<std::array<uint32_t, 4>> expected;
    for (size_t k = 0; k < L.dt.cells.size(); ++k)
      if (L.in_mesh[k]) {
        const auto& t = L.dt.cells[k];
        expected.push_back(
            {level.vertices[t[0]], level.vertices[t[1]], level.vertices[t[2]], level.vertices[t[3]]});
      }
    EXPECT_EQ(canonical_cells(level.carved_cells()), canonical_cells(expected));
    EXPECT_EQ(level.stats.tetrahedra, level.carved_cells().size());
    EXPECT_EQ(level.stats.vertices, level.vertices.size());
  }
}

TEST_P(HierarchyProperties, InsertingLayersCoarsestFirstRebuildsEveryLevel) {
  // What a decoder does: start from the coarsest level and insert each
  // finer level's new vertices as one batch into the same triangulation.
  const auto& levels = h().levels;
  IncrementalDelaunay dt;
  std::vector<uint32_t> have;
  for (size_t l = levels.size(); l-- > 0;) {
    std::vector<uint32_t> layer;
    std::set_difference(levels[l].vertices.begin(), levels[l].vertices.end(), have.begin(), have.end(),
                        std::back_inserter(layer));
    dt.insert(gather(c().points, layer), layer);
    have = levels[l].vertices;
    const auto pts = gather(c().points, have);
    EXPECT_EQ(test::cells_by_coords(dt.mesh(), c().points),
              test::cells_by_coords(delaunay_tetrahedralize(pts).value(), pts))
        << c().name << " level " << l;
  }
}

TEST_P(HierarchyProperties, RemovalCountsAddUp) {
  for (size_t l = 1; l < h().levels.size(); ++l) {
    const auto& s = h().levels[l].stats;
    EXPECT_EQ(s.removed_boundary + s.removed_interior,
              h().levels[l - 1].vertices.size() - h().levels[l].vertices.size());
    EXPECT_EQ(s.level, static_cast<int>(l));
  }
}

TEST_P(HierarchyProperties, IsDeterministic) {
  const Hierarchy again = build_hierarchy(c().points, c().options).value();
  ASSERT_EQ(again.levels.size(), h().levels.size());
  for (size_t l = 0; l < again.levels.size(); ++l)
    EXPECT_EQ(again.levels[l].vertices, h().levels[l].vertices);
}

// The greedy of §II.4 processes interior vertices by ascending importance:
// an interior vertex u that was kept although it comes before a removed
// neighbour v must have been locked by a removal that came before u.
TEST_P(HierarchyProperties, ImportanceOrderIsHonoured) {
  if (c().options.quality_guard > 0) GTEST_SKIP() << "the guard may skip vertices";
  for (size_t l = 0; l + 1 < h().levels.size(); ++l) {
    const auto& fine = h().levels[l].vertices;
    const LevelGeometry L = analyze_level(gather(c().points, fine), c().options.alpha).value();
    std::vector<uint8_t> removed(L.size(), 1);
    {
      const auto& coarse = h().levels[l + 1].vertices;
      for (uint32_t v = 0; v < L.size(); ++v)
        removed[v] = !std::binary_search(coarse.begin(), coarse.end(), fine[v]);
    }
    auto before = [&](uint32_t a, uint32_t b) {  // a is processed before b
      if (L.boundary[a] != L.boundary[b]) return L.boundary[a] != 0 && removed[a];
      const double ia = importance(L, a), ib = importance(L, b);
      return ia != ib ? ia < ib : a < b;
    };
    for (uint32_t u = 0; u < L.size(); ++u) {
      if (L.boundary[u] || removed[u]) continue;
      bool locked_in_time = false, has_removed_neighbour = false;
      for (uint32_t w : L.neighbors.row(u))
        if (removed[w]) {
          has_removed_neighbour = true;
          if ((L.boundary[w] != 0) || before(w, u)) locked_in_time = true;
        }
      EXPECT_TRUE(has_removed_neighbour) << c().name << " level " << l << ": interior vertex " << u
                                         << " was free yet kept (the set is not maximal)";
      if (has_removed_neighbour) {
        EXPECT_TRUE(locked_in_time) << c().name << " level " << l << ": interior vertex " << u
                                    << " was kept but none of its removed neighbours precedes it";
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, HierarchyProperties, ::testing::Range<size_t>(0, 6),
                         [](const auto& info) { return cases()[info.param].name; });

TEST(HierarchyStopping, RespectsLevelCountAndBaseSize) {
  const auto pts = test::load_quantized("bunny_10k").points;
  HierarchyOptions o = dmax(128);
  o.max_levels = 2;
  EXPECT_EQ(build_hierarchy(pts, o).value().levels.size(), 3u);
  o.max_levels = 0;
  o.min_base_vertices = 6000;
  const Hierarchy h = build_hierarchy(pts, o).value();
  EXPECT_GE(h.levels.back().vertices.size(), 6000u);
  EXPECT_GT(h.levels.size(), 1u);
}

TEST(HierarchyStopping, PaperRuleEndsAtTheFirstLevelWithoutBoundaryRemoval) {
  const auto pts = test::load_quantized("torus_288").points;
  const Hierarchy h = build_hierarchy(pts, dmax(335)).value();
  for (size_t l = 1; l + 1 < h.levels.size(); ++l)
    EXPECT_GT(h.levels[l].stats.removed_boundary, 0u) << "level " << l;
  EXPECT_EQ(h.levels.back().stats.removed_boundary, 0u);
}

// The quality floor stalls the paper preset on a TetGen quality mesh: it
// stops after the first level that removed less than 1% (HIERARCHY.md §7),
// where the paper's rule alone goes on (bunny_10k: 22 levels, not 16).
TEST(HierarchyStopping, PaperPresetEndsAfterAStalledLevel) {
  const auto pts = test::load_quantized("bunny_10k").points;
  HierarchyOptions o = dmax(128);
  o.average_quality_floor = 1.0;  // the paper preset's
  const Hierarchy h = build_hierarchy(pts, o).value();
  auto removed_share = [&](size_t l) {
    const auto& s = h.levels[l].stats;
    return static_cast<double>(s.removed_boundary + s.removed_interior) /
           static_cast<double>(h.levels[l - 1].vertices.size());
  };
  ASSERT_GT(h.levels.size(), 2u);
  for (size_t l = 1; l + 1 < h.levels.size(); ++l) EXPECT_GE(removed_share(l), 0.01) << "level " << l;
  const size_t last = h.levels.size() - 1;
  EXPECT_TRUE(removed_share(last) < 0.01 || h.levels[last].stats.removed_boundary == 0);
  o.stop_when_boundary_is_final = false;
  o.max_levels = static_cast<int>(h.levels.size());
  const Hierarchy longer = build_hierarchy(pts, o).value();
  EXPECT_GT(longer.levels.size(), h.levels.size()) << "the rule stopped a hierarchy that would have gone on";
}

TEST(HierarchyQuality, GuardRejectsRemovalsThatWouldCreateWorseCells) {
  const auto& plain = hierarchy_of(cases()[0]);
  const auto& guarded = hierarchy_of(cases()[5]);
  uint64_t rejected = 0;
  for (const auto& l : guarded.levels) rejected += l.stats.rejected_by_quality;
  EXPECT_GT(rejected, 0u);
  EXPECT_LT(guarded.levels[0].vertices.size() - guarded.levels[1].vertices.size(),
            plain.levels[0].vertices.size() - plain.levels[1].vertices.size());
}

// Boundary simplification on a shape whose answer is known: the grid cube
// with every cell kept. A vertex inside a face of the cube lies in the plane
// of its link (error 0); a corner or an edge vertex does not.
TEST(BoundarySimplification, FlatFaceVerticesAreCandidatesCornersAreNot) {
  const auto pts = test::full_grid(6);
  const LevelGeometry L = analyze_level(pts, {AlphaPolicy::Kind::kConvexHull, 0}).value();
  Csr nothing;
  nothing.offsets.assign(L.size() + 1, 0);
  const auto candidates = boundary_candidates(L, nothing, {}, 0.25);
  std::vector<uint8_t> is_candidate(L.size(), 0);
  for (const auto& cand : candidates) {
    is_candidate[cand.vertex] = 1;
    EXPECT_LE(cand.error, 0.25);
  }
  for (uint32_t v = 0; v < L.size(); ++v) {
    const GridPoint p = pts[v];
    const int on_faces = (p.x == 0 || p.x == 5) + (p.y == 0 || p.y == 5) + (p.z == 0 || p.z == 5);
    EXPECT_EQ(is_candidate[v] != 0, on_faces == 1) << "vertex (" << p.x << "," << p.y << "," << p.z << ")";
  }
}

TEST(BoundarySimplification, RepresentedOriginalPointsBoundTheError) {
  // The same cube face vertex, now standing for an original point 3 units
  // off the face plane: it stops being a candidate for Dmax < 3.
  const auto pts = test::full_grid(6);
  const LevelGeometry L = analyze_level(pts, {AlphaPolicy::Kind::kConvexHull, 0}).value();
  const uint32_t face_vertex = 0 * 36 + 2 * 6 + 3;  // (0, 2, 3) on the x = 0 face
  ASSERT_EQ(pts[face_vertex], (GridPoint{0, 2, 3}));
  const std::vector<GridPoint> originals = {{-3, 2, 3}};
  Csr represented;
  represented.offsets.assign(L.size() + 1, 0);
  for (size_t v = face_vertex + 1; v <= L.size(); ++v) represented.offsets[v] = 1;
  represented.items = {0};
  auto has = [&](double d) {
    for (const auto& cand : boundary_candidates(L, represented, originals, d))
      if (cand.vertex == face_vertex) return true;
    return false;
  };
  EXPECT_FALSE(has(2.9));
  EXPECT_TRUE(has(3.0));
}

}  // namespace
}  // namespace dtm

namespace dtm {
namespace {

// Every corpus model builds a full hierarchy with the README's settings
// (256-unit box, Dmax = 2, paper's alpha and stopping rule).
class CorpusHierarchy : public ::testing::TestWithParam<std::string> {};

TEST_P(CorpusHierarchy, BuildsToTheEnd) {
  const auto q = test::load_quantized(GetParam());
  const double extent = q.grid.step * ((1 << 14) - 1);
  HierarchyOptions o;
  o.dmax = 2.0 * (extent / 256) / q.grid.step;
  const Hierarchy h = build_hierarchy(q.points, o).value();
  ASSERT_GE(h.levels.size(), 2u) << GetParam();
  for (size_t l = 1; l < h.levels.size(); ++l) {
    EXPECT_LT(h.levels[l].vertices.size(), h.levels[l - 1].vertices.size());
    EXPECT_GT(h.levels[l].stats.tetrahedra, 0u);
    EXPECT_TRUE(std::isfinite(h.levels[l].stats.max_boundary_error));
    EXPECT_GT(h.levels[l].stats.avg_min_solid_angle, 0);
  }
  EXPECT_EQ(h.levels.back().stats.removed_boundary, 0u);
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusHierarchy, ::testing::ValuesIn(test::kCorpus),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace dtm

namespace dtm {
namespace {

// The choice of a coarser level's vertices (core/coarsening.cpp: the
// boundary's chord errors and the local spacing found on every core, the
// greedy passes on one) is the same on any number of threads, with boundary
// vertices fixed and free.
TEST(Coarsening, TheChoiceIsTheSameOnAnyNumberOfThreads) {
  std::mt19937 random(2026);
  std::uniform_int_distribution<int32_t> coordinate(0, 119);
  std::set<std::tuple<int32_t, int32_t, int32_t>> seen;
  std::vector<GridPoint> pts;
  while (pts.size() < 40000) {
    const GridPoint p{coordinate(random), coordinate(random), coordinate(random) / 2};
    if (seen.emplace(p.x, p.y, p.z).second) pts.push_back(p);
  }
  std::sort(pts.begin(), pts.end());
  const LevelGeometry L = analyze_level(pts, {AlphaPolicy::Kind::kConvexHull, 0}).value();
  const LevelSurface surface = level_surface(L);
  for (const double dmax : {0.25, 4.0}) {
    Coarsening one;
    {
      const test::Threads use(1);
      one = choose_coarser(L, surface, {0.5, dmax, kFirstBetaGuess});
    }
    ASSERT_GT(one.kept, L.size() / 4);
    ASSERT_LT(one.kept, L.size());
    for (int threads : {2, 3, 7}) {
      const test::Threads use(threads);
      const Coarsening many = choose_coarser(L, surface, {0.5, dmax, kFirstBetaGuess});
      EXPECT_EQ(many.keep, one.keep) << threads << " threads, D_max " << dmax;
      EXPECT_EQ(many.kept, one.kept);
      EXPECT_EQ(many.fixed, one.fixed);
      EXPECT_EQ(many.beta, one.beta);
    }
  }
}

}  // namespace
}  // namespace dtm
