// NearestSpacing (core/nearest_spacing.h), a bricked level's alpha, against
// every pair: clustered points, a lone far point (many rings out), points
// on one plane (cells far from cubic) and coordinates at the grid's edge;
// and points on a line across the grid, more cells than 8 bytes hold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "core/nearest_spacing.h"

namespace dtm {
namespace {

double brute_force(const std::vector<GridPoint>& points, size_t i) {
  int64_t best = std::numeric_limits<int64_t>::max();
  for (size_t j = 0; j < points.size(); ++j) {
    if (j == i) continue;
    const int64_t dx = points[j].x - points[i].x, dy = points[j].y - points[i].y,
                  dz = points[j].z - points[i].z;
    best = std::min(best, dx * dx + dy * dy + dz * dz);
  }
  return best == std::numeric_limits<int64_t>::max() ? 0 : std::sqrt(static_cast<double>(best));
}

std::vector<GridPoint> distinct(std::vector<GridPoint> points) {
  std::set<GridPoint> seen;
  std::vector<GridPoint> out;
  for (const GridPoint& p : points)
    if (seen.insert(p).second) out.push_back(p);
  return out;
}

TEST(NearestSpacing, EqualsTheNearestOfEveryPair) {
  std::mt19937 rng(11);
  const int32_t top = (1 << 24) - 1;
  std::vector<std::vector<GridPoint>> sets;
  {
    std::vector<GridPoint> clusters;  // dense clusters far apart, and a lone point
    std::uniform_int_distribution<int32_t> spread(-40, 40);
    for (const GridPoint centre : {GridPoint{1000, 1000, 1000}, GridPoint{60000, 2000, 900}})
      for (int i = 0; i < 700; ++i)
        clusters.push_back({centre.x + spread(rng), centre.y + spread(rng), centre.z + spread(rng)});
    clusters.push_back({65535, 65535, 65535});
    sets.push_back(distinct(clusters));
  }
  {
    std::vector<GridPoint> plane;  // flat: the cells' side comes from a thin box
    std::uniform_int_distribution<int32_t> at(0, 5000);
    for (int i = 0; i < 1500; ++i) plane.push_back({at(rng), at(rng), 7});
    sets.push_back(distinct(plane));
  }
  {
    std::vector<GridPoint> edge;  // the grid's corners and edges, and random points
    std::uniform_int_distribution<int32_t> at(0, top);
    for (const int32_t x : {0, top})
      for (const int32_t y : {0, top})
        for (const int32_t z : {0, top}) edge.push_back({x, y, z});
    for (int i = 0; i < 500; ++i) edge.push_back({at(rng), at(rng), at(rng)});
    sets.push_back(distinct(edge));
  }
  sets.push_back({{5, 5, 5}});  // a lone point: 0
  for (size_t s = 0; s < sets.size(); ++s) {
    const NearestSpacing nearest(sets[s]);
    for (size_t i = 0; i < sets[s].size(); ++i)
      ASSERT_EQ(nearest.nearest(i), brute_force(sets[s], i)) << "set " << s << ", point " << i;
  }
  {
    // Points on a line across the whole 24-bit grid, 8 apart give or take
    // 3: cells too many to pack in 8 bytes (2^21 a side), sorted by the
    // whole cell instead. The nearest on a line is a neighbour in x.
    std::vector<int32_t> xs;
    for (int32_t k = 0; k < (1 << 21); ++k) xs.push_back(8 * k + (k * 7) % 4);
    std::vector<GridPoint> line;
    for (int32_t x : xs) line.push_back({x, 0, 0});
    const NearestSpacing nearest(line);
    for (size_t i = 0; i < line.size(); i += 997) {
      int64_t best = std::numeric_limits<int64_t>::max();
      if (i > 0) best = std::min<int64_t>(best, xs[i] - xs[i - 1]);
      if (i + 1 < xs.size()) best = std::min<int64_t>(best, xs[i + 1] - xs[i]);
      ASSERT_EQ(nearest.nearest(i), static_cast<double>(best)) << "line point " << i;
    }
  }
  // A subset named by ids (a level's points among the grid's), in any order.
  const std::vector<GridPoint>& all = sets[0];
  std::vector<uint32_t> ids;
  for (uint32_t i = 0; i < all.size(); i += 3) ids.push_back(i);
  std::shuffle(ids.begin(), ids.end(), rng);
  std::vector<GridPoint> subset;
  for (uint32_t id : ids) subset.push_back(all[id]);
  const NearestSpacing nearest(all, ids);
  for (size_t i = 0; i < ids.size(); ++i)
    ASSERT_EQ(nearest.nearest(i), brute_force(subset, i)) << "subset point " << i;
}

}  // namespace
}  // namespace dtm
