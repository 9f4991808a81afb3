// The search trees built on every core (core/aabb_on_every_core.h,
// core/nearest_points.cpp) must be the trees CGAL builds on one thread:
// the same answers to the last bit, the same primitive among equally near
// ones, the same order of a traversal, whatever the number of threads. The
// points lie on a small grid, so that distances tie often.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "common/threads.h"
#include "core/aabb_on_every_core.h"
#include "core/nearest_points.h"
#include "test_support.h"

namespace dtm {
namespace {

using test::Threads;

using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

// n triangles with corners on a grid of `side` points a side.
std::vector<Triangle> grid_triangles(size_t n, int side, uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> at(0, side - 1), step(-3, 3);
  std::vector<Triangle> out;
  while (out.size() < n) {
    const K::Point_3 a(at(random), at(random), at(random));
    const K::Point_3 b(a.x() + step(random), a.y() + step(random), a.z() + step(random));
    const K::Point_3 c(a.x() + step(random), a.y() + step(random), a.z() + step(random));
    if (!CGAL::collinear(a, b, c)) out.emplace_back(a, b, c);
  }
  return out;
}

TEST(AabbOnEveryCore, AnswersAsCgalsOwnTreeOnAnyNumberOfThreads) {
  const std::vector<Triangle> soup = grid_triangles(40000, 120, 7);
  Tree cgal(soup.cbegin(), soup.cend());
  cgal.accelerate_distance_queries();
  cgal.build();

  std::mt19937 random(11);
  std::uniform_int_distribution<int> at(-10, 130);
  std::vector<K::Point_3> queries;
  for (int i = 0; i < 3000; ++i) queries.emplace_back(at(random), at(random), at(random));
  for (size_t i = 0; i < soup.size(); i += 97) queries.push_back(soup[i].vertex(1));  // on the surface
  std::vector<K::Segment_3> segments;
  for (int i = 0; i < 40; ++i)
    segments.emplace_back(K::Point_3(at(random), at(random), at(random)),
                          K::Point_3(at(random), at(random), at(random)));

  for (int threads : {1, 2, 3, 16}) {
    const Threads given(threads);
    Tree ours(soup.cbegin(), soup.cend());
    std::vector<Tree::Point_and_primitive_id> references;
    for (auto it = soup.cbegin(); it != soup.cend(); ++it) references.emplace_back(it->vertex(0), it);
    const DistanceHints<Tree> hints(references);
    build_on_every_core(ours);
    for (const K::Point_3& q : queries) {
      const auto hint = hints.nearest(q);
      const auto theirs = cgal.closest_point_and_primitive(q);
      const auto mine = ours.closest_point_and_primitive(q, hint);
      ASSERT_EQ(mine.first, theirs.first) << threads << " threads, query " << q;
      ASSERT_EQ(mine.second, theirs.second) << threads << " threads, query " << q;
      ASSERT_EQ(ours.squared_distance(q, hint.first), cgal.squared_distance(q)) << threads << " threads";
    }
    // A traversal lists what it meets in the order of the tree's nodes and
    // primitives: the same order, the same tree.
    for (const K::Segment_3& s : segments) {
      std::vector<Primitive::Id> a, b;
      cgal.all_intersected_primitives(s, std::back_inserter(a));
      ours.all_intersected_primitives(s, std::back_inserter(b));
      ASSERT_EQ(a, b) << threads << " threads";
    }
  }
}

TEST(AabbOnEveryCore, SmallAndEmptyTrees) {
  for (size_t n : {size_t{1}, size_t{2}, size_t{3}, size_t{5}}) {
    const std::vector<Triangle> soup = grid_triangles(n, 10, static_cast<uint32_t>(n));
    const Threads given(4);
    Tree cgal(soup.cbegin(), soup.cend()), ours(soup.cbegin(), soup.cend());
    cgal.accelerate_distance_queries();
    std::vector<Tree::Point_and_primitive_id> references;
    for (auto it = soup.cbegin(); it != soup.cend(); ++it) references.emplace_back(it->vertex(0), it);
    const DistanceHints<Tree> hints(references);
    build_on_every_core(ours);
    const K::Point_3 q(4, 5, 6);
    EXPECT_EQ(ours.closest_point_and_primitive(q, hints.nearest(q)), cgal.closest_point_and_primitive(q));
  }
  const DistanceHints<Tree> none({});
  EXPECT_TRUE(none.empty());
}

TEST(NearestPoints, VisitsInTheSameOrderOnAnyNumberOfThreads) {
  std::mt19937 random(3);
  std::uniform_int_distribution<int32_t> at(0, 60);
  std::vector<GridPoint> points(50000);
  for (GridPoint& p : points) p = {at(random), at(random), at(random)};
  const auto visits = [&](const NearestPoints& index, const std::array<double, 3>& centre) {
    std::vector<std::pair<uint32_t, double>> out;
    index.visit_nearest(centre, [&](uint32_t i, double d2) {
      out.emplace_back(i, d2);
      return out.size() < 200;
    });
    return out;
  };
  std::vector<std::array<double, 3>> centres;
  for (int i = 0; i < 300; ++i)
    centres.push_back({at(random) + 0.5 * (i % 2), double(at(random)), double(at(random))});
  std::vector<std::vector<std::pair<uint32_t, double>>> one;
  {
    const Threads given(1);
    const NearestPoints index(points);
    for (const auto& c : centres) one.push_back(visits(index, c));
  }
  for (int threads : {2, 5, 16}) {
    const Threads given(threads);
    const NearestPoints index(points);
    for (size_t i = 0; i < centres.size(); ++i) ASSERT_EQ(visits(index, centres[i]), one[i]) << threads;
  }
}

}  // namespace
}  // namespace dtm
