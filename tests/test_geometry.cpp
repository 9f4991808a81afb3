#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

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
