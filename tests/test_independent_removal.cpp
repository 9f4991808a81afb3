// Removing an independent set by refilling cavities must give exactly the
// Delaunay tetrahedralization built from scratch, neighbours included, on
// degenerate grids and on hull vertices.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "core/independent_removal.h"
#include "test_support.h"

namespace dtm {
namespace {

// A greedy random independent set of the edge graph.
std::vector<uint8_t> random_independent_set(const Csr& neighbors, uint32_t seed) {
  std::vector<uint32_t> order(neighbors.rows());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  std::vector<uint8_t> removed(order.size(), 0), locked(order.size(), 0);
  for (uint32_t v : order) {
    if (locked[v]) continue;
    removed[v] = locked[v] = 1;
    for (uint32_t u : neighbors.row(v)) locked[u] = 1;
  }
  return removed;
}

// Each cell with its four neighbours, all named by coordinates.
using CellWithNeighbours = std::pair<test::CellByCoords, std::vector<test::CellByCoords>>;

std::vector<CellWithNeighbours> describe(const TetMesh& mesh, const std::vector<GridPoint>& pts) {
  auto named = [&](int32_t c) {
    test::CellByCoords t{};  // a hull face names no cell: all zeros
    if (c < 0) return t;
    for (int i = 0; i < 4; ++i) t[i] = pts[mesh.cells[c][i]];
    std::sort(t.begin(), t.end());
    return t;
  };
  std::vector<CellWithNeighbours> out;
  for (size_t c = 0; c < mesh.cells.size(); ++c) {
    std::vector<test::CellByCoords> nbrs;
    for (int i = 0; i < 4; ++i) nbrs.push_back(named(mesh.neighbors[c][i]));
    std::sort(nbrs.begin(), nbrs.end());
    out.emplace_back(named(static_cast<int32_t>(c)), nbrs);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void expect_same_as_scratch(const std::vector<GridPoint>& pts, uint32_t seed) {
  const TetMesh dt = delaunay_tetrahedralize(pts).value();
  const Csr cells = vertex_cells(dt, pts.size());
  const Csr nbrs = vertex_neighbors(dt, cells);
  const auto removed = random_independent_set(nbrs, seed);
  std::vector<GridPoint> kept;
  for (size_t v = 0; v < pts.size(); ++v)
    if (!removed[v]) kept.push_back(pts[v]);
  const TetMesh fast = remove_independent_vertices(dt, cells, nbrs, pts, removed);
  EXPECT_EQ(describe(fast, kept), describe(delaunay_tetrahedralize(kept).value(), kept)) << "seed " << seed;
  for (size_t c = 0; c < fast.cells.size(); ++c)  // the neighbour relation is symmetric
    for (int i = 0; i < 4; ++i) {
      const int32_t n = fast.neighbors[c][i];
      if (n < 0) continue;
      EXPECT_EQ(std::count(fast.neighbors[n].begin(), fast.neighbors[n].end(), int32_t(c)), 1);
    }
}

TEST(IndependentRemoval, FullGridMatchesAFreshBuild) {
  for (uint32_t seed = 1; seed <= 3; ++seed) expect_same_as_scratch(test::full_grid(8), seed);
}

TEST(IndependentRemoval, RandomFiveBitGridMatchesAFreshBuild) {
  for (uint32_t seed = 1; seed <= 3; ++seed)
    expect_same_as_scratch(test::random_grid_points(1500, 5, seed), seed);
}

TEST(IndependentRemoval, CorpusModelMatchesAFreshBuild) {
  expect_same_as_scratch(test::load_quantized("torus_288_grid").points, 5);
  expect_same_as_scratch(test::load_quantized("fandisk_11k").points, 6);
}

}  // namespace
}  // namespace dtm
