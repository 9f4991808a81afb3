// CGAL's AABB tree, and the first guesses of its distance queries, built on
// every core into the trees CGAL builds on one thread: the same answers to
// the last bit.
//
// CGAL builds the tree depth first on one thread: each node takes the box
// of its primitives, puts their median along the box's longest axis in the
// middle (nth_element) and makes its two halves the same way. A distance
// query starts from a guess, the nearest primitive's reference point in a
// k-d tree, which CGAL also builds on one thread
// (accelerate_distance_queries()). Together about 1.5 s of one thread in a
// 40 s encode of bunny_1m, the shape measure's trees remade each repair
// round (docs/SPEED_AND_MEMORY.md).
//
// build_on_every_core(tree) computes every node's box and split first, the
// two halves of a large node on two threads, and keeps the boxes in the
// order CGAL makes its nodes (a node, then its first half's nodes, then its
// second's); CGAL's own build then runs on them (custom_build()), each box
// read back, nothing split again. Each node's computation is CGAL's own
// functor on the same range in the same state: the same primitive order and
// the same boxes as tree.build().
//
// build_kd_tree_on_every_core(tree) is CGAL's parallel k-d tree build (its
// splits are the sequential build's), here and for core/nearest_points.cpp.
//
// DistanceHints is the k-d tree accelerate_distance_queries() makes: its
// search tree's type over the primitives' reference points in the order
// they were inserted, built by CGAL's parallel build, whose splits are the
// sequential build's. nearest(q) is the guess CGAL's own query takes, so
// tree.squared_distance(q, hints.nearest(q).first) is
// tree.squared_distance(q), and the same for closest_point_and_primitive.
#pragma once

#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_tree/internal/AABB_search_tree.h>

#include <cstddef>
#include <vector>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "common/tbb_threads.h"
#endif

#include "common/threads.h"

namespace dtm {

namespace aabb_detail {

// Below this many primitives a node's two halves are made on its thread.
constexpr size_t kHalvesApart = 8192;

// Makes node `node` of the primitives [first, beyond) (`range` of them) and
// those below it, as AABB_tree::expand() does, its boxes into `boxes` by
// CGAL's node numbers (a subtree of r primitives has r - 1 nodes).
template <class Traits, class Iterator, class Box>
void make_nodes(const Traits& traits, Iterator first, Iterator beyond, size_t range, size_t node,
                std::vector<Box>& boxes) {
  boxes[node] = traits.compute_bbox_object()(first, beyond);
  traits.split_primitives_object()(first, beyond, boxes[node]);
  if (range == 2) return;  // two leaves
  if (range == 3) {        // a leaf, and a node of two
    make_nodes(traits, first + 1, beyond, 2, node + 1, boxes);
    return;
  }
  const size_t half = range / 2;
  const auto low = [&] { make_nodes(traits, first, first + half, half, node + 1, boxes); };
  const auto high = [&] { make_nodes(traits, first + half, beyond, range - half, node + half, boxes); };
#ifdef CGAL_LINKED_WITH_TBB
  if (range >= kHalvesApart) {
    tbb::parallel_invoke(low, high);
    return;
  }
#endif
  low();
  high();
}

}  // namespace aabb_detail

// tree.build() on thread_count() threads (the tree's primitives inserted).
template <class Tree>
void build_on_every_core(Tree& tree) {
#ifdef CGAL_LINKED_WITH_TBB
  const int threads = thread_count();
  if (threads <= 1 || tree.size() < aabb_detail::kHalvesApart) {
    tree.build();
    return;
  }
  using Traits = typename Tree::AABB_traits;
  using Box = typename Traits::Bounding_box;
  const Traits& traits = tree.traits();
  std::vector<Box> boxes;
  size_t next = 0;
  // CGAL asks for the root's box first, with every primitive: all the
  // nodes are made then; later calls read their boxes in CGAL's order.
  const auto box_of = [&](auto first, auto beyond) -> Box {
    if (boxes.empty()) {
      const auto range = static_cast<size_t>(beyond - first);
      boxes.resize(range - 1);
      tbb::task_arena arena(arena_threads());
      arena.execute([&] { aabb_detail::make_nodes(traits, first, beyond, range, 0, boxes); });
    }
    return boxes.at(next++);
  };
  const auto split_nothing = [](auto, auto, const Box&) {};
  tree.custom_build(box_of, split_nothing);
#else
  tree.build();
#endif
}

// tree.build() of a CGAL k-d tree on thread_count() threads: CGAL's parallel
// build, whose splits are its sequential build's (a node's two halves
// apart), so searches walk the same tree.
template <class KdTree>
void build_kd_tree_on_every_core(KdTree& tree) {
#ifdef CGAL_LINKED_WITH_TBB
  if (const int threads = thread_count(); threads > 1) {
    tbb::task_arena arena(arena_threads());
    arena.execute([&] { tree.template build<CGAL::Parallel_tag>(); });
    return;
  }
#endif
  tree.build();
}

// The guesses CGAL's distance queries start from, found as CGAL finds them.
template <class Tree>
class DistanceHints {
 public:
  using Traits = typename Tree::AABB_traits;
  using Point = typename Tree::Point;
  using Hint = typename Tree::Point_and_primitive_id;

  // `references`: each primitive's reference point and id, in the order
  // the primitives were inserted into the tree.
  explicit DistanceHints(const std::vector<Hint>& references) {
    std::vector<Decorated> points;
    points.reserve(references.size());
    for (const Hint& r : references) points.emplace_back(r.first, r.second);
    empty_ = points.empty();
    tree_.insert(points.begin(), points.end());
    if (!empty_) build_kd_tree_on_every_core(tree_);
  }

  // The reference point nearest q, and its primitive (not for no primitives).
  Hint nearest(const Point& q) const {
    const Search search(tree_, q, 1);
    return Hint(static_cast<Point>(search.begin()->first), search.begin()->first.id());
  }
  bool empty() const { return empty_; }

 private:
  using SearchTree = CGAL::AABB_search_tree<Traits>;
  using Search = typename SearchTree::Neighbor_search;
  using Decorated = typename CGAL::Add_decorated_point<Traits, typename Traits::Primitive::Id>::Point_3;
  typename Search::Tree tree_;
  bool empty_ = true;
};

}  // namespace dtm
