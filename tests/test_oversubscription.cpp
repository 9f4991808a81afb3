// More threads than cores must end, and export the same mesh: an MPI rank
// per core's share whose thread pool is as wide as the node is that case
// (docs/ARCHITECTURE.md §5.9). The parallel insertion's retries spun on
// cells whose holders were not running: 300k points that take 4 s on the
// cores' worth of threads did not end in 120 s on four times as many. A
// program of its own, so that ctest bounds it (tests/CMakeLists.txt): a
// stall fails it by its deadline, not the suite by CI's.
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <array>
#include <random>
#include <set>
#include <span>
#include <thread>
#include <vector>

#include "common/threads.h"
#include "mesh/delaunay.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

// `count` distinct points, coordinates below 2^bits: at 6 bits, a lattice
// where most cells have cospherical neighbours (the grid's case).
std::vector<GridPoint> random_points(size_t count, uint32_t seed, int bits = 14) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int32_t> coord(0, (1 << bits) - 1);
  std::set<GridPoint> set;
  while (set.size() < count) set.insert({coord(rng), coord(rng), coord(rng)});
  return {set.begin(), set.end()};
}

// The exported mesh whole: the cells, each one's corners in their order,
// and the neighbours. Everything the encoder computes from a cell in
// floating point follows its corners' order, so the canonical export fixes
// it too, not only the set of cells (mesh/delaunay.cpp canonical_corners):
// otherwise the encoder's bytes varied from run to run wherever its
// triangulations were built by several threads.
void expect_same_mesh(const TetMesh& a, const TetMesh& b) {
  EXPECT_EQ(a.cells.size(), b.cells.size());
  EXPECT_TRUE(a.cells == b.cells);
  EXPECT_TRUE(a.neighbors == b.neighbors);
}

// Restores the process's thread count whatever a test asked.
struct Threads {
  explicit Threads(int n) : allow(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(n)) {
    set_thread_count(n);
  }
  ~Threads() { set_thread_count(0); }
  tbb::global_control allow;
};

TEST(Oversubscribed, FourTimesTheCoresExportTheSameMesh) {
  ASSERT_TRUE(parallel_delaunay_available());
  for (const auto& points : {random_points(300000, 5), random_points(100000, 7, 6)}) {
    TetMesh alone;
    {
      const Threads one(1);
      alone = delaunay_tetrahedralize(points).value();
    }
    const Threads many(4 * cores_given() + 2);
    expect_same_mesh(delaunay_tetrahedralize(points).value(), alone);
  }
}

// Three "ranks" at once in one process, each as wide as four times the
// cores: 12 times the cores' worth of threads inserting.
TEST(Oversubscribed, SeveralTriangulationsAtOnceEachWiderThanTheMachine) {
  const auto points = random_points(150000, 6);
  TetMesh alone;
  {
    const Threads one(1);
    alone = delaunay_tetrahedralize(points).value();
  }
  const Threads many(4 * cores_given() + 2);
  std::vector<TetMesh> made(3);
  std::vector<std::thread> ranks;
  for (auto& m : made) ranks.emplace_back([&] { m = delaunay_tetrahedralize(points).value(); });
  for (auto& r : ranks) r.join();
  for (const auto& m : made) expect_same_mesh(m, alone);
}

// The export after a second batch (the encoder's repairs, a level built on
// the one before) copies the cells the batch left and sorts the new ones:
// the same mesh as one built at once on one thread.
TEST(Oversubscribed, APatchedExportIsTheWholeExport) {
  const auto points = random_points(90000, 8, 6);
  std::vector<uint32_t> ids(points.size());
  for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
  TetMesh alone;
  {
    const Threads one(1);
    IncrementalDelaunay dt;
    ASSERT_TRUE(dt.insert(points, ids).ok());
    alone = dt.mesh();
  }
  const Threads many(4 * cores_given() + 2);
  IncrementalDelaunay dt;
  const size_t half = points.size() / 2;
  const std::span<const GridPoint> p(points);
  const std::span<const uint32_t> id(ids);
  ASSERT_TRUE(dt.insert(p.first(half), id.first(half)).ok());
  std::vector<int32_t> previous;
  const TetMesh before = dt.mesh(previous);
  ASSERT_TRUE(dt.insert(p.subspan(half), id.subspan(half)).ok());
  expect_same_mesh(dt.mesh(before, previous), alone);
}

// The per-vertex cell lists (atomic counts and cursors, each row sorted
// after) and the boundary (its passes' faces found in slices): on any
// number of threads what one pass in cell order gives.
TEST(Oversubscribed, CellListsAndTheBoundaryAreThoseOfOnePassInOrder) {
  const auto points = random_points(40000, 9);
  const TetMesh dt = delaunay_tetrahedralize(points).value();
  std::vector<std::vector<uint32_t>> rows(points.size());
  for (uint32_t c = 0; c < dt.cells.size(); ++c)
    for (uint32_t v : dt.cells[c]) rows[v].push_back(c);
  std::vector<std::array<uint32_t, 3>> one_thread_boundary;
  {
    const Threads one(1);
    one_thread_boundary = boundary_triangles(dt.cells, 20000);  // several passes
  }
  ASSERT_FALSE(one_thread_boundary.empty());
  const Threads many(4 * cores_given() + 2);
  const Csr incident = vertex_cells(dt, points.size());
  ASSERT_EQ(incident.rows(), points.size());
  for (size_t v = 0; v < points.size(); ++v) {
    const auto row = incident.row(v);
    ASSERT_TRUE(std::equal(row.begin(), row.end(), rows[v].begin(), rows[v].end())) << "vertex " << v;
  }
  EXPECT_EQ(boundary_triangles(dt.cells, 20000), one_thread_boundary);
  EXPECT_EQ(boundary_triangles(dt.cells), one_thread_boundary);
}

}  // namespace
}  // namespace dtm
