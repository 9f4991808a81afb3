#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "mesh/delaunay.h"
#include "mesh/geometry.h"
#include "mesh/predicates.h"

namespace dtm {
namespace {

// A regular tetrahedron: alternate corners of a cube.
const std::array<Vec3, 4> kRegular = {Vec3{0, 0, 0}, Vec3{1, 1, 0}, Vec3{1, 0, 1}, Vec3{0, 1, 1}};

TEST(Geometry, RegularTetrahedronSolidAngleIsThePapersValue) {
  for (double a : solid_angles(kRegular)) EXPECT_NEAR(a, 0.551286, 5e-7);
  EXPECT_NEAR(kRegularTetSolidAngle, 3 * std::acos(1.0 / 3) - kPi, 1e-15);
}

TEST(Geometry, SolidAngleMatchesDihedralFormulaOfThePaper) {
  // Eq. 2.2: solid angle at A = sum of the dihedral angles at AB, AC, AD - pi.
  const std::array<Vec3, 4> t = {Vec3{0, 0, 0}, Vec3{5, 1, 0}, Vec3{1, 4, 1}, Vec3{2, 1, 7}};
  auto dihedral = [](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {  // at edge ab, faces abc and abd
    const Vec3 e = b - a;
    const Vec3 n1 = cross(e, c - a), n2 = cross(e, d - a);
    return std::acos(dot(n1, n2) / (norm(n1) * norm(n2)));
  };
  const double expected = dihedral(t[0], t[1], t[2], t[3]) + dihedral(t[0], t[2], t[1], t[3]) +
                          dihedral(t[0], t[3], t[1], t[2]) - kPi;
  EXPECT_NEAR(solid_angles(t)[0], expected, 1e-12);
}

TEST(Geometry, OctantCornerIsAnEighthOfTheSphere) {
  const std::array<Vec3, 4> t = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
  EXPECT_NEAR(solid_angles(t)[0], kFullSolidAngle / 8, 1e-14);
}

TEST(Geometry, VolumeAndCircumradius) {
  // |det| of the edge vectors (1,1,0), (1,0,1), (0,1,1) is 2: volume 1/3.
  const double v = signed_volume(kRegular[0], kRegular[1], kRegular[2], kRegular[3]);
  EXPECT_NEAR(std::abs(v), 1.0 / 3, 1e-15);
  EXPECT_EQ(signed_volume(kRegular[0], kRegular[2], kRegular[1], kRegular[3]), -v);
  EXPECT_NEAR(signed_volume({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), 1.0 / 6, 1e-15);
  // The regular tetrahedron inscribed in the unit cube has the cube's circumsphere.
  EXPECT_NEAR(circumradius(kRegular[0], kRegular[1], kRegular[2], kRegular[3]), std::sqrt(3.0) / 2, 1e-15);
  EXPECT_TRUE(std::isinf(circumradius({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0})));
}

using Corners = std::array<GridPoint, 4>;

TEST(Predicates, InteriorsMeetTellsOverlapFromTouching) {
  const Corners a = {GridPoint{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  EXPECT_TRUE(interiors_meet(a, a));
  // Reflected through the face x + y + z = 10: a shared face only.
  const Corners across = {GridPoint{10, 0, 0}, {0, 10, 0}, {0, 0, 10}, {7, 7, 7}};
  EXPECT_FALSE(interiors_meet(a, across));
  // Sharing an edge, a corner; lying against a's face with no corner shared.
  EXPECT_FALSE(interiors_meet(a, {GridPoint{0, 0, 0}, {10, 0, 0}, {0, -10, 0}, {0, 0, -10}}));
  EXPECT_FALSE(interiors_meet(a, {GridPoint{0, 0, 0}, {-10, 0, 0}, {0, -10, 0}, {0, 0, -10}}));
  EXPECT_FALSE(interiors_meet(a, {GridPoint{1, 1, 0}, {3, 1, 0}, {1, 3, 0}, {1, 1, -5}}));
  // Inside a, and pushed through its face by one step.
  EXPECT_TRUE(interiors_meet(a, {GridPoint{1, 1, 1}, {3, 1, 1}, {1, 3, 1}, {1, 1, 3}}));
  EXPECT_TRUE(interiors_meet(a, {GridPoint{1, 1, 1}, {3, 1, 1}, {1, 3, 1}, {1, 1, -5}}));
  // Two tetrahedra round edges that pass each other (one along x, one along
  // y, a step apart in z): no face's plane separates them, only the plane
  // of both edges' directions; one step lower, the edges cross.
  const Corners below = {GridPoint{-10, 0, 0}, {10, 0, 0}, {0, 10, -10}, {0, -10, -10}};
  const Corners above = {GridPoint{0, -10, 1}, {0, 10, 1}, {10, 0, 11}, {-10, 0, 11}};
  EXPECT_FALSE(interiors_meet(below, above));
  EXPECT_FALSE(interiors_meet(above, below));
  const Corners lower = {GridPoint{0, -10, -1}, {0, 10, -1}, {10, 0, 9}, {-10, 0, 9}};
  EXPECT_TRUE(interiors_meet(below, lower));
  EXPECT_TRUE(interiors_meet(lower, below));
  // Edges in one plane, at their ends: touching, not meeting.
  const Corners level = {GridPoint{0, -10, 0}, {0, 10, 0}, {10, 0, 10}, {-10, 0, 10}};
  EXPECT_FALSE(interiors_meet(below, level));
  // At the grid's far corners.
  constexpr int32_t m = (1 << kMaxQBits) - 1;
  const Corners big = {GridPoint{0, 0, 0}, {m, 0, 0}, {0, m, 0}, {0, 0, m}};
  EXPECT_TRUE(interiors_meet(big, {GridPoint{m - 2, 1, 0}, {1, m - 2, 0}, {1, 1, m - 2}, {m, m, m}}));
  EXPECT_FALSE(interiors_meet(big, {GridPoint{m, 1, 0}, {1, m, 0}, {0, 1, m}, {m, m, m}}));
}

// A Delaunay tetrahedralization tiles its hull: no two of its cells meet,
// and a tetrahedron of its vertices that is not one of them meets two or
// more (inside one cell, its corners would be that cell's).
TEST(Predicates, InteriorsMeetAgreesWithATiling) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int32_t> u(0, 60);
  std::vector<GridPoint> points;
  for (int i = 0; i < 60; ++i) points.push_back({u(rng), u(rng), u(rng)});
  const auto dt = delaunay_tetrahedralize(points);
  ASSERT_TRUE(dt.ok());
  const auto corners = [&](const std::array<uint32_t, 4>& c) {
    return Corners{points[c[0]], points[c[1]], points[c[2]], points[c[3]]};
  };
  for (size_t i = 0; i < dt->cells.size(); ++i)
    for (size_t j = i + 1; j < dt->cells.size(); ++j)
      ASSERT_FALSE(interiors_meet(corners(dt->cells[i]), corners(dt->cells[j]))) << i << " " << j;
  std::set<std::array<uint32_t, 4>> cells;
  for (auto c : dt->cells) std::sort(c.begin(), c.end()), cells.insert(c);
  std::uniform_int_distribution<uint32_t> pick(0, static_cast<uint32_t>(points.size() - 1));
  for (int tried = 0; tried < 2000;) {
    std::array<uint32_t, 4> t = {pick(rng), pick(rng), pick(rng), pick(rng)};
    if (orientation(points[t[0]], points[t[1]], points[t[2]], points[t[3]]) == 0) continue;
    ++tried;
    size_t meets = 0;
    for (const auto& c : dt->cells) meets += interiors_meet(corners(t), corners(c));
    std::sort(t.begin(), t.end());
    EXPECT_EQ(meets == 1, cells.count(t) != 0) << meets;
    EXPECT_GE(meets, 1u);
  }
  // Each cell meets itself alone.
  for (const auto& t : dt->cells) {
    size_t meets = 0;
    for (const auto& c : dt->cells) meets += interiors_meet(corners(t), corners(c));
    EXPECT_EQ(meets, 1u);
  }
}

}  // namespace
// A positively oriented cell, its corners listed in any of their 24 orders
// (12 of which keep it positive): the parity of the sort gives what the
// exact orientation test gives.
TEST(Geometry, SortedPositiveByParityIsTheOrientationTests) {
  const std::vector<GridPoint> points = {{0, 0, 0}, {7, 1, 0}, {2, 9, 1}, {3, 2, 8}, {5, 5, 5}};
  std::array<uint32_t, 4> cell = {0, 1, 2, 3};
  if (orientation(points[0], points[1], points[2], points[3]) < 0) std::swap(cell[2], cell[3]);
  std::array<int, 4> order = {0, 1, 2, 3};
  int positive = 0;
  do {
    const std::array<uint32_t, 4> listed = {cell[order[0]], cell[order[1]], cell[order[2]], cell[order[3]]};
    if (orientation(points[listed[0]], points[listed[1]], points[listed[2]], points[listed[3]]) <= 0)
      continue;
    ++positive;
    EXPECT_EQ(sorted_positive(listed), sorted_positive(listed, points));
  } while (std::next_permutation(order.begin(), order.end()));
  EXPECT_EQ(positive, 12);
}

}  // namespace dtm
