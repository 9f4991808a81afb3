// Hexahedra, prisms and pyramids as tetrahedra (tools/formats/cell_split.h):
// the tetrahedra fill the cell exactly (their volumes add up to its own,
// each positively oriented), and two cells sharing a face split it alike
// whatever the numbering, so a conforming mesh stays conforming.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "tools/formats/cell_split.h"

namespace dtm {
namespace {

using Point = std::array<double, 3>;
using Tet = std::array<uint32_t, 4>;

double volume(const std::vector<Point>& p, const Tet& t) {
  const auto d = [&](int k, int a) {
    return p[t[static_cast<size_t>(k)]][static_cast<size_t>(a)] - p[t[0]][static_cast<size_t>(a)];
  };
  return (d(1, 0) * (d(2, 1) * d(3, 2) - d(2, 2) * d(3, 1)) -
          d(1, 1) * (d(2, 0) * d(3, 2) - d(2, 2) * d(3, 0)) +
          d(1, 2) * (d(2, 0) * d(3, 1) - d(2, 1) * d(3, 0))) /
         6;
}

// The triangles on a cell's boundary: faces of one tetrahedron only.
std::set<std::array<uint32_t, 3>> boundary(const std::vector<Tet>& tets) {
  std::map<std::array<uint32_t, 3>, int> count;
  for (const Tet& t : tets)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<uint32_t, 3> f{};
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) f[static_cast<size_t>(j++)] = t[static_cast<size_t>(k)];
      std::sort(f.begin(), f.end());
      ++count[f];
    }
  std::set<std::array<uint32_t, 3>> out;
  for (const auto& [f, n] : count)
    if (n == 1) out.insert(f);
  return out;
}

// Two unit cubes side by side (x in [0,1] and [1,2]), a prism and a
// pyramid on top of the first, their corners numbered at random: every
// split fills its cell, and the shared faces' triangles are the same
// from both sides.
TEST(CellSplit, CellsAreFilledAndSharedFacesSplitAlike) {
  const std::vector<Point> grid = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},      {0, 1, 0}, {0, 0, 1},
                                   {1, 0, 1}, {1, 1, 1}, {0, 1, 1},      {2, 0, 0}, {2, 1, 0},
                                   {2, 0, 1}, {2, 1, 1}, {0.5, 0.5, 1.6}};
  // Local cells in gmsh's and VTK's corner order.
  const std::vector<uint32_t> left = {0, 1, 2, 3, 4, 5, 6, 7};     // hexahedron
  const std::vector<uint32_t> right = {1, 8, 9, 2, 5, 10, 11, 6};  // hexahedron, sharing 1 2 6 5
  const std::vector<uint32_t> pyramid = {4, 5, 6, 7, 12};          // on the left cube's top
  const std::vector<uint32_t> prism = {0, 1, 4, 3, 2, 7};          // the left cube's half, as a wedge
  std::mt19937 random(7);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<uint32_t> number(grid.size());
    std::iota(number.begin(), number.end(), 0u);
    std::shuffle(number.begin(), number.end(), random);
    std::vector<Point> p(grid.size());
    std::vector<InputPoint> at(grid.size());
    for (size_t i = 0; i < grid.size(); ++i)
      p[number[i]] = grid[i], at[number[i]] = {grid[i][0], grid[i][1], grid[i][2]};
    const auto split = [&](const std::vector<uint32_t>& local) {
      std::vector<uint32_t> corners;
      for (uint32_t v : local) corners.push_back(number[v]);
      std::vector<Tet> out;
      split_cell(corners, at, out);
      return out;
    };
    const auto a = split(left), b = split(right), c = split(pyramid), w = split(prism);
    ASSERT_EQ(a.size(), 6u);
    ASSERT_EQ(c.size(), 2u);
    ASSERT_EQ(w.size(), 3u);
    const auto total = [&](const std::vector<Tet>& tets) {
      double v = 0;
      for (const Tet& t : tets) {
        EXPECT_GT(volume(p, t), 1e-12) << "a flat or negatively oriented tetrahedron";
        v += volume(p, t);
      }
      return v;
    };
    EXPECT_NEAR(total(a), 1.0, 1e-12);
    EXPECT_NEAR(total(b), 1.0, 1e-12);
    EXPECT_NEAR(total(c), 0.6 / 3, 1e-12);
    EXPECT_NEAR(total(w), 0.5, 1e-12);
    // The tetrahedra of the two cubes and the pyramid make one conforming
    // mesh: its boundary is the union's (the two cubes' 10 quadrilaterals
    // but the one under the pyramid, and the pyramid's 4 sides: 22
    // triangles), with no face left over inside.
    std::vector<Tet> all = a;
    all.insert(all.end(), b.begin(), b.end());
    all.insert(all.end(), c.begin(), c.end());
    EXPECT_EQ(boundary(all).size(), 9u * 2 + 4) << "trial " << trial;
    // A quadrilateral alone splits as the cells split it.
    const auto halves = split_quad({number[1], number[2], number[6], number[5]});
    const auto outside = boundary(a);
    for (auto h : halves) {
      std::sort(h.begin(), h.end());
      EXPECT_TRUE(outside.contains(h)) << "trial " << trial;
    }
  }
  // A prism and a pyramid stored as collapsed hexahedra (a corner given
  // twice): no tetrahedron with a repeated corner, the rest fills them.
  {
    const std::vector<InputPoint> at = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}};
    std::vector<Tet> prism, pyramid;
    split_cell(std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 5, 4}, at, prism);
    split_cell(std::vector<uint32_t>{0, 1, 2, 3, 4, 4, 4, 4}, at, pyramid);
    std::vector<Point> p;
    for (const InputPoint& q : at) p.push_back({q.x, q.y, q.z});
    for (const auto& [tets, want] : {std::pair{prism, 0.5}, std::pair{pyramid, 1.0 / 3}}) {
      double v = 0;
      for (const Tet& t : tets) {
        EXPECT_EQ(std::set<uint32_t>(t.begin(), t.end()).size(), 4u);
        EXPECT_GT(volume(p, t), 1e-12);
        v += volume(p, t);
      }
      EXPECT_NEAR(v, want, 1e-12);
    }
  }
  // Other counts split nothing.
  std::vector<Tet> none;
  const std::vector<InputPoint> seven(7);
  split_cell(std::vector<uint32_t>{0, 1, 2, 3}, seven, none);
  split_cell(std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6}, seven, none);
  EXPECT_TRUE(none.empty());
}

}  // namespace
}  // namespace dtm
