#include "core/nearest_points.h"

#include <CGAL/Orthogonal_incremental_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/property_map.h>

#include <numeric>
#include <utility>
#include <vector>

#include "core/aabb_on_every_core.h"

namespace dtm {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
// The tree holds indices; their points are looked up in the state's array.
using PointOf = CGAL::Pointer_property_map<Point>::const_type;
using Traits = CGAL::Search_traits_adapter<uint32_t, PointOf, CGAL::Search_traits_3<K>>;
using Distance =
    CGAL::Distance_adapter<uint32_t, PointOf, CGAL::Euclidean_distance<CGAL::Search_traits_3<K>>>;
using Search = CGAL::Orthogonal_incremental_neighbor_search<Traits, Distance>;
using Tree = Search::Tree;

}  // namespace

struct NearestPoints::State {
  std::vector<Point> points;
  std::unique_ptr<Tree> tree;
};

NearestPoints::NearestPoints(std::span<const GridPoint> points) : state_(std::make_unique<State>()) {
  State& s = *state_;
  // No tree for no points (a property map over an empty array would name
  // its first element).
  if (points.empty()) return;
  s.points.reserve(points.size());
  for (const GridPoint& p : points) s.points.emplace_back(p.x, p.y, p.z);
  std::vector<uint32_t> ids(points.size());
  std::iota(ids.begin(), ids.end(), 0u);
  const PointOf point_of = CGAL::make_property_map(std::as_const(s.points));
  s.tree = std::make_unique<Tree>(ids.begin(), ids.end(), Tree::Splitter(), Traits(point_of));
  // Built now, not lazily by the first search: searches may run at once.
  build_kd_tree_on_every_core(*s.tree);
}

NearestPoints::~NearestPoints() = default;

void NearestPoints::visit_nearest(const std::array<double, 3>& centre,
                                  const std::function<bool(uint32_t, double)>& visit) const {
  const State& s = *state_;
  if (s.points.empty()) return;
  const PointOf point_of = CGAL::make_property_map(s.points);
  Search search(*s.tree, Point(centre[0], centre[1], centre[2]), 0.0, true, Distance(point_of));
  for (auto it = search.begin(); it != search.end(); ++it)
    if (!visit(it->first, it->second)) return;
}

}  // namespace dtm
