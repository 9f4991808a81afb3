// The thread shares (common/threads.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <random>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "common/first_touch.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/threads.h"
#include "mesh/delaunay.h"
#include "mesh/owned_lock_grid.h"
#include "mesh/topology.h"
#include "test_support.h"

namespace dtm {
namespace {

// A share holds for the thread that made it, while it lives.
TEST(ThreadShare, HoldsForItsThreadWhileItLives) {
  const int before = thread_count();
  {
    const ThreadShare share(3);
    EXPECT_EQ(thread_count(), 3);
    int other = 0;
    std::thread([&] { other = thread_count(); }).join();
    EXPECT_EQ(other, before);
    {
      const ThreadShare inner(1);
      EXPECT_EQ(thread_count(), 1);
    }
    EXPECT_EQ(thread_count(), 3);
  }
  EXPECT_EQ(thread_count(), before);
}

// Pieces side by side: even shares; a piece that ends gives its threads to
// the one at work holding the fewest, never making the shares at work more
// than the threads; a piece's share is its thread's while its Use lives.
TEST(ThreadShares, APieceThatEndsGivesItsThreadsToThoseAtWork) {
  ThreadShares shares(7, 3);
  EXPECT_EQ(shares.share(0), 3);
  EXPECT_EQ(shares.share(1), 2);
  EXPECT_EQ(shares.share(2), 2);
  {
    const ThreadShares::Use first(shares, 1);
    EXPECT_EQ(thread_count(), 2);
    {
      const ThreadShare inner(1);  // the innermost share holds
      EXPECT_EQ(thread_count(), 1);
    }
    shares.end(2);
    EXPECT_EQ(thread_count(), 4);  // piece 1 held the fewest
    EXPECT_EQ(shares.share(0), 3);
    EXPECT_EQ(shares.share(2), 0);
  }
  EXPECT_EQ(shares.share(1), 0);
  EXPECT_EQ(shares.share(0), 7);
  shares.end(0);
  EXPECT_EQ(shares.share(0), 0);

  // More pieces than threads: one each, and none grows while the others
  // still hold more than the threads.
  ThreadShares crowded(2, 4);
  for (int k = 0; k < 4; ++k) EXPECT_EQ(crowded.share(k), 1);
  crowded.end(0);
  crowded.end(1);
  EXPECT_EQ(crowded.share(2), 1);
  EXPECT_EQ(crowded.share(3), 1);
  crowded.end(2);
  EXPECT_EQ(crowded.share(3), 2);
}

// Two pieces one after the other on one thread (the stream writer with one
// thread): the second never gets more than the one.
TEST(ThreadShares, PiecesInTurnOnOneThreadKeepOne) {
  ThreadShares shares(1, 2);
  { const ThreadShares::Use first(shares, 0); }
  const ThreadShares::Use second(shares, 1);
  EXPECT_EQ(thread_count(), 1);
}

TEST(ParallelHelpers, CollectInOrderIsWhatALoopAppends) {
  for (size_t n : {size_t{0}, size_t{1}, size_t{5}, size_t{100000}})
    for (size_t block : {size_t{1}, size_t{7}, size_t{4096}}) {
      std::vector<size_t> want;
      for (size_t i = 0; i < n; ++i)
        if (i % 3 != 1) want.push_back(i * i);
      const auto got = collect_in_order<size_t>(n, block, [](size_t first, size_t last, auto& out) {
        for (size_t i = first; i < last; ++i)
          if (i % 3 != 1) out.push_back(i * i);
      });
      EXPECT_EQ(got, want) << n << " by " << block;
    }
}

// Every item once, item 0 before any other, on any number of threads and
// items (the runs handed out and the last short one).
TEST(ParallelHelpers, ParallelForRunsEachItemOnceAndTheFirstAlone) {
  for (int threads : {1, 2, 3, 7})
    for (size_t n : {size_t{0}, size_t{1}, size_t{2}, size_t{3}, size_t{17}, size_t{1000}, size_t{100003}}) {
      const test::Threads use(threads);
      std::vector<std::atomic<int>> runs(n);
      std::atomic<bool> first_done{false};
      std::atomic<int> before_first{0};
      std::mutex seen_lock;
      std::set<std::thread::id> seen;
      parallel_for(n, [&](size_t i) {
        if (i == 0) {
          first_done = true;
        } else if (!first_done) {
          ++before_first;
        }
        ++runs[i];
        if (i % 97 == 0) {
          const std::lock_guard<std::mutex> hold(seen_lock);
          seen.insert(std::this_thread::get_id());
        }
      });
      for (size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i], 1) << i << " of " << n << " on " << threads;
      EXPECT_EQ(before_first, 0) << n << " on " << threads;
      EXPECT_LE(seen.size(), static_cast<size_t>(threads)) << n << " on " << threads;
    }
}

// The parallel insertion's locks (mesh/owned_lock_grid.h): a grid cell one
// thread holds fails another's attempt until the holder lets go; "but one"
// keeps that one; a thread's list follows it from one grid to the next.
TEST(OwnedLockGrid, ACellHeldByOneThreadIsRefusedToAnotherUntilLetGo) {
  struct P {
    double px, py, pz;
    double x() const { return px; }
    double y() const { return py; }
    double z() const { return pz; }
  };
  OwnedLockGrid grid(CGAL::Bbox_3(0, 0, 0, 10, 10, 10), 10);
  const P a{0.5, 0.5, 0.5}, a_too{0.9, 0.1, 0.2}, b{5.5, 5.5, 5.5}, c{9.99, 9.99, 9.99};
  const auto elsewhere = [&](auto&& f) {
    bool r = false;
    std::thread t([&] { r = f(); });
    t.join();
    return r;
  };
  // Whether another thread can take the cells around p (letting go at once).
  const auto lockable_elsewhere = [&](const P& p, int radius) {
    return elsewhere([&] {
      const bool got = grid.try_lock(p, radius);
      grid.unlock_all_points_locked_by_this_thread();
      return got;
    });
  };
  ASSERT_TRUE(grid.try_lock(a));
  EXPECT_TRUE(grid.try_lock(a_too));  // the same grid cell, held already
  EXPECT_TRUE(grid.is_locked_by_this_thread(a_too));
  EXPECT_FALSE(grid.is_locked_by_this_thread(b));
  ASSERT_TRUE(grid.try_lock(b));
  EXPECT_FALSE(elsewhere([&] { return grid.try_lock(a); }));
  EXPECT_FALSE(elsewhere([&] { return grid.is_locked_by_this_thread(a); }));
  // A radius takes the cells around: c's is free, b's is held.
  EXPECT_FALSE(lockable_elsewhere(P{6.5, 6.5, 6.5}, 1));
  EXPECT_TRUE(lockable_elsewhere(c, 1));
  // A failed attempt with a radius lets go of what it took, not of what the
  // thread held before: this thread holds (3,3,3), the last cell of the
  // cube around (2,2,2) taken; the other thread keeps its (8,8,8) and frees
  // the 26 cells it took.
  ASSERT_TRUE(grid.try_lock(P{3.5, 3.5, 3.5}));
  EXPECT_TRUE(elsewhere([&] {
    const bool before = grid.try_lock(P{8.5, 8.5, 8.5});
    const bool failed = !grid.try_lock(P{2.5, 2.5, 2.5}, 1);
    const bool kept = grid.is_locked_by_this_thread(P{8.5, 8.5, 8.5});
    const bool freed =
        !grid.is_locked_by_this_thread(P{1.5, 1.5, 1.5}) && !grid.is_locked_by_this_thread(P{3.5, 3.5, 2.5});
    grid.unlock_all_points_locked_by_this_thread();
    return before && failed && kept && freed;
  }));
  EXPECT_TRUE(grid.try_lock(P{1.5, 1.5, 1.5}));
  EXPECT_TRUE(grid.try_lock(P{3.5, 3.5, 2.5}));
  grid.unlock_all_tls_locked_locations_but_one_point(b);
  EXPECT_TRUE(lockable_elsewhere(a, 0));
  EXPECT_FALSE(elsewhere([&] { return grid.try_lock(b); }));
  EXPECT_TRUE(grid.is_locked_by_this_thread(b));
  grid.unlock_all_points_locked_by_this_thread();
  EXPECT_TRUE(lockable_elsewhere(b, 0));
  // Points outside the box lock the nearest border cell.
  ASSERT_TRUE(grid.try_lock(P{-3, -3, -3}));
  EXPECT_FALSE(elsewhere([&] { return grid.try_lock(a); }));
  grid.unlock_all_points_locked_by_this_thread();
  // Another grid, then this one again: nothing is held over.
  OwnedLockGrid other(CGAL::Bbox_3(0, 0, 0, 1, 1, 1), 4);
  ASSERT_TRUE(other.try_lock(P{0.1, 0.1, 0.1}));
  other.unlock_all_points_locked_by_this_thread();
  ASSERT_TRUE(grid.try_lock(c));
  grid.unlock_all_points_locked_by_this_thread();
  EXPECT_TRUE(lockable_elsewhere(c, 0));
}

TEST(ParallelHelpers, ParallelSortIsStdSort) {
  std::vector<std::pair<uint32_t, uint32_t>> items;
  uint64_t x = 12345;
  for (uint32_t i = 0; i < 200000; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    items.emplace_back(static_cast<uint32_t>(x >> 40) % 1000, i);
  }
  auto want = items;
  std::sort(want.begin(), want.end());
  parallel_sort(items.begin(), items.end());
  EXPECT_EQ(items, want);
}

// Each vertex's cells ascending and its neighbours ascending, as one pass
// in cell order lists them, on any number of threads: for a mesh in the
// canonical order (a thread's corners in long runs) and for its cells
// shuffled (every cell anywhere).
TEST(ParallelHelpers, VertexCellsAndNeighboursAreOnePassesOnAnyNumberOfThreads) {
  const std::vector<GridPoint> points = test::random_grid_points(12000, 10, 7);
  TetMesh mesh = delaunay_tetrahedralize(points).value();
  ASSERT_GT(mesh.cells.size(), size_t{1} << 15);  // the threads' path
  for (const bool shuffled : {false, true}) {
    if (shuffled) std::shuffle(mesh.cells.begin(), mesh.cells.end(), std::mt19937(3));
    const Csr want_cells = build_csr(points.size(), [&](auto&& emit) {
      for (uint32_t c = 0; c < mesh.cells.size(); ++c)
        for (uint32_t v : mesh.cells[c]) emit(v, c);
    });
    const Csr want_neighbours = build_csr(points.size(), [&](auto&& emit) {
      for (uint32_t v = 0; v < points.size(); ++v) {
        std::vector<uint32_t> around;
        for (uint32_t c : want_cells.row(v))
          for (uint32_t u : mesh.cells[c])
            if (u != v) around.push_back(u);
        std::sort(around.begin(), around.end());
        around.erase(std::unique(around.begin(), around.end()), around.end());
        for (uint32_t u : around) emit(v, u);
      }
    });
    for (const int threads : {1, 2, 3, 8, 16}) {
      set_thread_count(threads);
      const Csr cells = vertex_cells(mesh, points.size());
      EXPECT_EQ(cells.offsets, want_cells.offsets) << threads << " threads, shuffled " << shuffled;
      EXPECT_EQ(cells.items, want_cells.items) << threads << " threads, shuffled " << shuffled;
      const Csr neighbours = vertex_neighbors(mesh, cells);
      EXPECT_EQ(neighbours.offsets, want_neighbours.offsets) << threads << " threads";
      EXPECT_EQ(neighbours.items, want_neighbours.items) << threads << " threads";
    }
    set_thread_count(0);
  }
}

// The canonical cell order (cells ascending by their sorted corners) is one
// sort's on any number of threads: its buckets are filled through atomic
// cursors, in any order, and sorted after. For cells in that order already
// (the identity) and shuffled, and for a list with a cell twice (ties go to
// the lower index, as a stable sort's).
TEST(ParallelHelpers, CanonicalCellOrderIsOneSortsOnAnyNumberOfThreads) {
  const std::vector<GridPoint> points = test::random_grid_points(30000, 10, 5);
  TetMesh mesh = delaunay_tetrahedralize(points).value();
  ASSERT_GT(mesh.cells.size(), size_t{1} << 17);  // more than one range of the passes
  auto sorted = [](std::array<uint32_t, 4> c) {
    std::sort(c.begin(), c.end());
    return c;
  };
  std::vector<std::array<uint32_t, 4>> cells = mesh.cells;
  std::sort(cells.begin(), cells.end(), [&](const auto& a, const auto& b) { return sorted(a) < sorted(b); });
  for (const int variant : {0, 1, 2}) {
    if (variant == 1) std::shuffle(cells.begin(), cells.end(), std::mt19937(5));
    if (variant == 2) cells.push_back(cells[cells.size() / 3]);
    std::vector<uint32_t> want(cells.size());
    for (uint32_t k = 0; k < want.size(); ++k) want[k] = k;
    std::stable_sort(want.begin(), want.end(),
                     [&](uint32_t a, uint32_t b) { return sorted(cells[a]) < sorted(cells[b]); });
    for (const int threads : {1, 2, 3, 8, 16}) {
      set_thread_count(threads);
      EXPECT_EQ(canonical_cell_order(cells), want) << threads << " threads, variant " << variant;
    }
    set_thread_count(0);
  }
}

// Growing with the pages touched on every core is resize() and assign():
// what the vector held stays, the new elements are zeros (or the value),
// whether the storage is grown or reserved already, below the threshold
// and past it, on any number of threads (the touched storage starts right
// after the last element, on no page boundary).
TEST(ParallelHelpers, GrowingOnEveryCoreIsResizeAndAssign) {
  const size_t big = 3 * kFirstTouchInParallelFrom / sizeof(uint32_t) + 13;
  for (const int threads : {1, 2, 3, 8, 16})
    for (const bool reserved : {false, true})
      for (const size_t n : {size_t{0}, size_t{1000}, big}) {
        set_thread_count(threads);
        std::vector<uint32_t> v(777);
        for (uint32_t i = 0; i < v.size(); ++i) v[i] = i * 2654435761u | 1;
        const std::vector<uint32_t> before = v;
        if (reserved) v.reserve(n + 5000);
        resize_on_every_core(v, v.size() + n);
        ASSERT_EQ(v.size(), before.size() + n);
        EXPECT_TRUE(std::equal(before.begin(), before.end(), v.begin()));
        EXPECT_TRUE(std::all_of(v.begin() + static_cast<std::ptrdiff_t>(before.size()), v.end(),
                                [](uint32_t x) { return x == 0; }))
            << threads << " threads, " << n << " more";
        assign_on_every_core(v, n, uint32_t{0xDEADBEEF});
        ASSERT_EQ(v.size(), n);
        EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](uint32_t x) { return x == 0xDEADBEEF; }));
        // Shrinking is resize's.
        resize_on_every_core(v, n / 2);
        EXPECT_EQ(v.size(), n / 2);
      }
  set_thread_count(0);
}

// More threads than a few a core only wait for each other (and each loop
// starts its own): a count asked above kMostThreadsPerCore a core given is
// held to that; below, it is what was asked.
TEST(Threads, AskedCountsAreHeldToAFewACore) {
  const int most = kMostThreadsPerCore * cores_given();
  EXPECT_EQ(threads_allowed(0), 0);
  EXPECT_EQ(threads_allowed(1), 1);
  EXPECT_EQ(threads_allowed(most), most);
  EXPECT_EQ(threads_allowed(most + 1), most);
  EXPECT_EQ(threads_allowed(4096), std::min(4096, most));
}

// for_each_item: each item once, on any number of threads, and an
// exception an item throws is thrown again once all are done (the lowest
// item's), the others still run.
TEST(ParallelHelpers, ForEachItemRunsEachOnceAndThrowsTheLowestItemsError) {
  for (const int threads : {1, 2, 3, 8}) {
    set_thread_count(threads);
    for (const size_t n : {size_t{0}, size_t{1}, size_t{2}, size_t{7}, size_t{100}}) {
      std::vector<std::atomic<int>> ran(n);
      for_each_item(n, [&](size_t k) { ++ran[k]; });
      for (size_t k = 0; k < n; ++k) EXPECT_EQ(ran[k].load(), 1) << k << " of " << n << ", " << threads;
    }
    std::vector<std::atomic<int>> ran(9);
    try {
      for_each_item(9, [&](size_t k) {
        ++ran[k];
        if (k == 3 || k == 6) throw std::runtime_error("item " + std::to_string(k));
      });
      ADD_FAILURE() << "nothing thrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 3");
    }
    for (size_t k = 0; k < 9; ++k) EXPECT_EQ(ran[k].load(), 1) << k;
  }
  set_thread_count(0);
}

}  // namespace
}  // namespace dtm
