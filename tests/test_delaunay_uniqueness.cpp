// docs/ARCHITECTURE.md §3.2: on degenerate (massively cospherical) grid input, the
// Delaunay tetrahedralization is one function of the point set: any insertion
// order, batch insertion level by level, and vertex removal give the same cells.
#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <set>

#include "common/threads.h"
#include "mesh/delaunay.h"
#include "mesh/topology.h"
#include "test_support.h"

namespace dtm {
namespace {

using test::cells_by_coords;

std::vector<uint32_t> iota_ids(size_t n) {
  std::vector<uint32_t> ids(n);
  std::iota(ids.begin(), ids.end(), 0u);
  return ids;
}

std::vector<test::CellByCoords> reference(const std::vector<GridPoint>& pts) {
  return cells_by_coords(delaunay_tetrahedralize(pts).value(), pts);
}

std::vector<test::CellByCoords> one_by_one(const std::vector<GridPoint>& pts, uint32_t seed) {
  std::vector<uint32_t> order = iota_ids(pts.size());
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  std::vector<GridPoint> shuffled;
  for (uint32_t i : order) shuffled.push_back(pts[i]);
  IncrementalDelaunay dt;
  dt.insert_one_by_one(shuffled, order);
  return cells_by_coords(dt.mesh(), pts);
}

// Inserts a random 1/8 first, then the rest in three batches.
std::vector<test::CellByCoords> in_batches(const std::vector<GridPoint>& pts, uint32_t seed) {
  std::vector<uint32_t> order = iota_ids(pts.size());
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  const size_t cuts[] = {0, pts.size() / 8, pts.size() * 2 / 5, pts.size() * 3 / 4, pts.size()};
  IncrementalDelaunay dt;
  for (int b = 0; b < 4; ++b) {
    std::vector<uint32_t> ids(order.begin() + cuts[b], order.begin() + cuts[b + 1]);
    std::vector<GridPoint> batch;
    for (uint32_t i : ids) batch.push_back(pts[i]);
    dt.insert(batch, ids);
  }
  return cells_by_coords(dt.mesh(), pts);
}

// Builds the superset, removes `drop` of its points one by one; the result
// must equal the direct build of the remaining points.
void expect_removal_matches_direct_build(const std::vector<GridPoint>& pts, size_t drop, uint32_t seed) {
  std::vector<uint32_t> order = iota_ids(pts.size());
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  std::vector<GridPoint> removed, kept;
  for (size_t k = 0; k < order.size(); ++k) (k < drop ? removed : kept).push_back(pts[order[k]]);
  IncrementalDelaunay dt;
  dt.insert(pts, iota_ids(pts.size()));
  dt.remove(removed);
  ASSERT_EQ(dt.number_of_vertices(), kept.size());
  EXPECT_EQ(cells_by_coords(dt.mesh(), pts), reference(kept));
}

class DegenerateGrid : public ::testing::TestWithParam<int> {
 protected:
  std::vector<GridPoint> points() const {
    return GetParam() == 0 ? test::full_grid(8) : test::random_grid_points(1500, 5, GetParam());
  }
};

TEST_P(DegenerateGrid, AnyInsertionOrderGivesTheSameCells) {
  const auto pts = points();
  const auto ref = reference(pts);
  ASSERT_FALSE(ref.empty());
  for (uint32_t seed = 1; seed <= 4; ++seed) EXPECT_EQ(one_by_one(pts, seed), ref) << "seed " << seed;
}

TEST_P(DegenerateGrid, BatchInsertionGivesTheSameCells) {
  const auto pts = points();
  const auto ref = reference(pts);
  for (uint32_t seed = 1; seed <= 4; ++seed) EXPECT_EQ(in_batches(pts, seed), ref) << "seed " << seed;
}

TEST_P(DegenerateGrid, RemovalGivesTheSameCellsAsADirectBuild) {
  const auto pts = points();
  expect_removal_matches_direct_build(pts, pts.size() / 5, 7);
  expect_removal_matches_direct_build(pts, pts.size() / 2, 8);
}

INSTANTIATE_TEST_SUITE_P(Grids, DegenerateGrid, ::testing::Values(0, 11, 12), [](const auto& info) {
  return info.param == 0 ? std::string("Full8x8x8") : "Random5Bit_" + std::to_string(info.param);
});

// Batches of 20,000 points and more go to every core (Parallel_tag): the
// threads insert in an order the scheduler decides, which the symbolic
// perturbation must not see. A full 30^3 lattice is as cospherical as input
// gets; it is inserted in parallel (one batch), one point at a time, and as
// a parallel batch into a triangulation that holds a random share already:
// a tenth (too few vertices for the threads: the batch starts one point at
// a time) or a quarter (the threads start at once, a decoder's finer layer).
TEST(DelaunayUniqueness, ParallelBatchesGiveTheSameCells) {
  ASSERT_TRUE(parallel_delaunay_available()) << "the native build links TBB";
  const auto pts = test::full_grid(33);
  const auto parallel = reference(pts);
  IncrementalDelaunay sequential;
  ASSERT_TRUE(sequential.insert_one_by_one(pts, iota_ids(pts.size())).ok());
  EXPECT_EQ(cells_by_coords(sequential.mesh(), pts), parallel);

  for (const size_t share : {10, 4}) {
    std::vector<uint32_t> order = iota_ids(pts.size());
    std::shuffle(order.begin(), order.end(), std::mt19937(5));
    std::vector<GridPoint> first, rest;
    std::vector<uint32_t> first_ids, rest_ids;
    for (size_t k = 0; k < order.size(); ++k) {
      (k < order.size() / share ? first : rest).push_back(pts[order[k]]);
      (k < order.size() / share ? first_ids : rest_ids).push_back(order[k]);
    }
    ASSERT_GE(rest.size(), 20000u) << "a batch the threads share";
    if (share == 4) {
      ASSERT_GE(first.size(), 4096u) << "no point inserted alone";
    }
    IncrementalDelaunay two_batches;
    ASSERT_TRUE(two_batches.insert(first, first_ids).ok());
    ASSERT_TRUE(two_batches.insert(rest, rest_ids).ok());
    EXPECT_EQ(cells_by_coords(two_batches.mesh(), pts), parallel) << "a 1/" << share << " share first";
  }
}

// A construction given one thread takes CGAL's sequential type (no locks,
// no concurrent container), given more the parallel one: the same export,
// cell for cell and neighbour for neighbour, on the lattice.
TEST(DelaunayUniqueness, OneThreadsSequentialTypeGivesTheParallelTypesExport) {
  ASSERT_TRUE(parallel_delaunay_available()) << "the native build links TBB";
  const auto pts = test::full_grid(33);
  ASSERT_GE(pts.size(), 20000u) << "a batch the threads share";
  const StatusOr<TetMesh> parallel = [&] {
    const test::Threads two(2);
    IncrementalDelaunay made_on_two;
    EXPECT_TRUE(made_on_two.parallel());
    return delaunay_tetrahedralize(pts);
  }();
  const test::Threads one_thread(1);
  const StatusOr<TetMesh> sequential = delaunay_tetrahedralize(pts);
  ASSERT_TRUE(parallel.ok() && sequential.ok());
  EXPECT_EQ(parallel->cells, sequential->cells);
  EXPECT_EQ(parallel->neighbors, sequential->neighbors);

  // An IncrementalDelaunay made on one thread: two batches, a removal and
  // the patched export give the whole export of what it holds.
  IncrementalDelaunay one;
  EXPECT_FALSE(one.parallel());
  const std::vector<uint32_t> ids = iota_ids(pts.size());
  const size_t half = pts.size() / 2;
  ASSERT_TRUE(one.insert(std::span(pts).first(half), std::span(ids).first(half)).ok());
  std::vector<int32_t> previous;
  const TetMesh before = one.mesh(previous);
  ASSERT_TRUE(one.insert(std::span(pts).subspan(half), std::span(ids).subspan(half)).ok());
  ASSERT_TRUE(one.remove(std::span(pts).subspan(half, 1)).ok());
  ASSERT_TRUE(one.insert(std::span(pts).subspan(half, 1), std::span(ids).subspan(half, 1)).ok());
  const TetMesh patched = one.mesh(before, previous);
  EXPECT_EQ(patched.cells, parallel->cells);
  EXPECT_EQ(patched.neighbors, parallel->neighbors);
}

// A triangulation built on every core holds its cells in the order the
// threads made them; the export gives them in the canonical order (sorted
// vertex ids), with neighbours that match, so that nothing computed from it
// depends on the threads.
TEST(DelaunayUniqueness, ExportIsInTheCanonicalOrder) {
  const auto pts = test::random_grid_points(40000, 9, 31);
  const TetMesh mesh = delaunay_tetrahedralize(pts).value();
  auto sorted = [](std::array<uint32_t, 4> c) {
    std::sort(c.begin(), c.end());
    return c;
  };
  for (size_t c = 1; c < mesh.cells.size(); ++c) ASSERT_LT(sorted(mesh.cells[c - 1]), sorted(mesh.cells[c]));
  for (size_t c = 0; c < mesh.cells.size(); ++c)
    for (int i = 0; i < 4; ++i) {
      const int32_t n = mesh.neighbors[c][i];
      if (n < 0) continue;
      // The neighbour shares the three corners other than corner i.
      int shared = 0;
      for (int j = 0; j < 4; ++j)
        if (j != i)
          shared += std::count(mesh.cells[static_cast<size_t>(n)].begin(),
                               mesh.cells[static_cast<size_t>(n)].end(), mesh.cells[c][j]);
      ASSERT_EQ(shared, 3);
    }
}

// canonical_cell_order puts any listing of the cells, in any order and with
// each cell's vertices in any order, into the export's order.
TEST(DelaunayUniqueness, CanonicalOrderOfAnyListingIsTheExports) {
  const auto pts = test::random_grid_points(20000, 9, 37);
  const TetMesh mesh = delaunay_tetrahedralize(pts).value();
  std::vector<std::array<uint32_t, 4>> listing = mesh.cells;
  std::mt19937 rng(3);
  std::shuffle(listing.begin(), listing.end(), rng);
  for (auto& c : listing) std::rotate(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(rng() % 4), c.end());
  const std::vector<uint32_t> order = canonical_cell_order(listing);
  ASSERT_EQ(order.size(), listing.size());
  for (size_t k = 0; k < order.size(); ++k) {
    std::array<uint32_t, 4> a = listing[order[k]], b = mesh.cells[k];
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    ASSERT_EQ(a, b) << "place " << k;
  }
  EXPECT_EQ(canonical_cell_order(mesh.cells), iota_ids(mesh.cells.size())) << "the export is in order";
}

// The export says which cells a later insertion left alone: their index in
// the previous export; the others are new (-1) and are exactly the cells the
// previous export did not have.
TEST(DelaunayUniqueness, ExportTellsWhichCellsAreNew) {
  const auto pts = test::random_grid_points(3000, 6, 21);
  std::vector<GridPoint> first(pts.begin(), pts.begin() + 2900), later(pts.begin() + 2900, pts.end());
  std::vector<uint32_t> ids = iota_ids(pts.size());
  IncrementalDelaunay dt;
  ASSERT_TRUE(dt.insert(first, std::span(ids).first(2900)).ok());
  std::vector<int32_t> previous;
  const TetMesh before = dt.mesh(previous);
  for (int32_t p : previous) EXPECT_EQ(p, -1);
  ASSERT_TRUE(dt.insert(later, std::span(ids).subspan(2900)).ok());
  const TetMesh after = dt.mesh(previous);
  ASSERT_EQ(previous.size(), after.cells.size());
  auto sorted = [](std::array<uint32_t, 4> c) {
    std::sort(c.begin(), c.end());
    return c;
  };
  std::set<std::array<uint32_t, 4>> old_cells;
  for (const auto& c : before.cells) old_cells.insert(sorted(c));
  size_t kept = 0;
  for (size_t c = 0; c < after.cells.size(); ++c) {
    const bool was_there = old_cells.count(sorted(after.cells[c])) > 0;
    EXPECT_EQ(previous[c] >= 0, was_there);
    if (previous[c] >= 0) {
      EXPECT_EQ(sorted(before.cells[static_cast<size_t>(previous[c])]), sorted(after.cells[c]));
      ++kept;
    }
  }
  EXPECT_GT(kept, after.cells.size() / 2);
}

// The export after local edits, given the previous one, is the whole
// canonical export: the same cells in the same order with the same
// neighbours, and the same previous indices. Rounds of a few insertions on
// degenerate grid points, some outside the convex hull so far, and a removal.
TEST(DelaunayUniqueness, PatchedExportIsTheWholeExport) {
  const auto pts = test::random_grid_points(4000, 7, 33);
  std::vector<uint32_t> ids = iota_ids(pts.size());
  // The first batch is the points nearest the middle: later ones are
  // outside its hull too.
  std::vector<uint32_t> order = ids;
  auto spread = [&](uint32_t i) {
    const GridPoint& p = pts[i];
    return std::abs(p.x - 64) + std::abs(p.y - 64) + std::abs(p.z - 64);
  };
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return spread(a) < spread(b); });
  IncrementalDelaunay patched, whole;
  std::vector<GridPoint> batch;
  std::vector<uint32_t> batch_ids;
  auto take = [&](size_t from, size_t to) {
    batch.clear();
    batch_ids.clear();
    for (size_t k = from; k < to; ++k) batch.push_back(pts[order[k]]), batch_ids.push_back(order[k]);
  };
  take(0, 3000);
  ASSERT_TRUE(patched.insert(batch, batch_ids).ok());
  ASSERT_TRUE(whole.insert(batch, batch_ids).ok());
  TetMesh mesh;
  std::vector<int32_t> previous, expected_previous;
  mesh = patched.mesh(mesh, previous);
  TetMesh expected = whole.mesh(expected_previous);
  ASSERT_EQ(mesh.cells, expected.cells);
  for (size_t from = 3000; from < 4000; from += 250) {
    take(from, from + 250);
    ASSERT_TRUE(patched.insert(batch, batch_ids).ok());
    ASSERT_TRUE(whole.insert(batch, batch_ids).ok());
    if (from == 3500) {
      const std::vector<GridPoint> gone = {pts[order[10]], pts[order[20]]};
      ASSERT_TRUE(patched.remove(gone).ok());
      ASSERT_TRUE(whole.remove(gone).ok());
    }
    mesh = patched.mesh(mesh, previous);
    expected = whole.mesh(expected_previous);
    ASSERT_EQ(mesh.cells, expected.cells) << "after the batch from " << from;
    ASSERT_EQ(mesh.neighbors, expected.neighbors) << "after the batch from " << from;
    ASSERT_EQ(previous, expected_previous) << "after the batch from " << from;
  }
}

TEST(DelaunayUniqueness, TheGridReallyIsDegenerate) {
  // A unit cube of 8 cospherical points has many Delaunay tetrahedralizations;
  // the 8x8x8 grid has 343 such cubes. The symbolic perturbation must still
  // produce a valid triangulation of the cube's volume: the cells of the
  // 8x8x8 grid fill its 7^3 volume exactly.
  const auto pts = test::full_grid(8);
  const TetMesh mesh = delaunay_tetrahedralize(pts).value();
  double volume = 0;
  for (const auto& c : mesh.cells) {
    auto v = [&](int i) { return pts[c[i]]; };
    const double ax = v(1).x - v(0).x, ay = v(1).y - v(0).y, az = v(1).z - v(0).z;
    const double bx = v(2).x - v(0).x, by = v(2).y - v(0).y, bz = v(2).z - v(0).z;
    const double cx = v(3).x - v(0).x, cy = v(3).y - v(0).y, cz = v(3).z - v(0).z;
    const double det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    ASSERT_GT(det, 0) << "every finite cell is positively oriented and not flat";
    volume += det / 6;
  }
  EXPECT_NEAR(volume, 343.0, 1e-9);
}

TEST(DelaunayUniqueness, CoplanarInputIsRejected) {
  std::vector<GridPoint> flat;
  for (int x = 0; x < 5; ++x)
    for (int y = 0; y < 5; ++y) flat.push_back({x, y, 3});
  EXPECT_EQ(delaunay_tetrahedralize(flat).status().code(), StatusCode::kInvalidInput);
  EXPECT_EQ(delaunay_tetrahedralize(std::vector<GridPoint>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).status().code(),
            StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace dtm
