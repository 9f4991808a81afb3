// The locks a parallel Delaunay insertion takes (mesh/delaunay.cpp): CGAL's
// lock-data-structure interface (what Triangulation_3 calls of its
// Lock_data_structure), on a grid of cells over the points' box, each cell
// free or owned by one thread. A thread inserting a point locks the grid
// cells of every corner of the cells it reads or changes; a cell another
// thread owns makes the attempt fail, and the thread lets go of all it holds
// and tries again later (never waits).
//
// Why not CGAL's Spatial_lock_grid_3<Tag_non_blocking>: it keeps which cells
// a thread holds in two TBB thread-specific tables, a grid of flags a
// thread and a list, and looks both up (a hash of the thread) at every lock,
// several times a cell: on bunny_1m those lookups took about 3 s of the
// parallel insertion's 19 s of CPU on two cores. Here each grid cell holds
// its owner's number, so "do I hold it" is one load, and the list is a
// thread_local vector.
#pragma once

#include <CGAL/Bbox_3.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/status.h"

namespace dtm {

class OwnedLockGrid {
 public:
  OwnedLockGrid(const CGAL::Bbox_3& box, int cells_per_axis)
      : box_(box),
        n_(std::max(1, cells_per_axis)),
        // (value-initialized: every cell free)
        owner_(std::make_unique<std::atomic<uint32_t>[]>(static_cast<size_t>(n_) * n_ * n_)) {
    const double n = n_;
    scale_[0] = n / std::max(box.xmax() - box.xmin(), 1e-300);
    scale_[1] = n / std::max(box.ymax() - box.ymin(), 1e-300);
    scale_[2] = n / std::max(box.zmax() - box.zmin(), 1e-300);
  }
  OwnedLockGrid(const OwnedLockGrid&) = delete;
  OwnedLockGrid& operator=(const OwnedLockGrid&) = delete;

  const CGAL::Bbox_3& get_bbox() const { return box_; }

  // Locks the grid cell of p (and those within lock_radius cells of it):
  // true if this thread holds them all afterwards.
  template <class P3>
  bool try_lock(const P3& p, int lock_radius = 0) {
    const int x = axis(p.x(), 0, box_.xmin()), y = axis(p.y(), 1, box_.ymin()),
              z = axis(p.z(), 2, box_.zmin());
    if (lock_radius == 0) return try_lock_cell(index(x, y, z));
    // On a failure, what this call took is let go (as CGAL's grid does);
    // what the thread held before stays held.
    std::vector<int>& held = held_here();
    const size_t before = held.size();
    for (int i = std::max(0, x - lock_radius); i <= std::min(n_ - 1, x + lock_radius); ++i)
      for (int j = std::max(0, y - lock_radius); j <= std::min(n_ - 1, y + lock_radius); ++j)
        for (int k = std::max(0, z - lock_radius); k <= std::min(n_ - 1, z + lock_radius); ++k)
          if (!try_lock_cell(index(i, j, k))) {
            for (size_t t = before; t < held.size(); ++t) owner_[held[t]].store(0, std::memory_order_release);
            held.resize(before);
            return false;
          }
    return true;
  }

  template <class P3>
  bool is_locked_by_this_thread(const P3& p) const {
    return owner_[grid_index(p)].load(std::memory_order_relaxed) == thread_number();
  }

  void unlock_all_points_locked_by_this_thread() {
    std::vector<int>& held = held_here();
    for (const int cell : held) owner_[cell].store(0, std::memory_order_release);
    held.clear();
  }

  template <class P3>
  void unlock_all_tls_locked_locations_but_one_point(const P3& p) {
    const int keep = grid_index(p);
    std::vector<int>& held = held_here();
    bool kept = false;
    for (const int cell : held) {
      if (cell == keep)
        kept = true;
      else
        owner_[cell].store(0, std::memory_order_release);
    }
    held.clear();
    if (kept) held.push_back(keep);
  }

 private:
  // This thread's number, 1, 2, ... (0 is a free cell), the same for every
  // grid.
  static uint32_t thread_number() {
    static std::atomic<uint32_t> threads_seen{0};
    thread_local const uint32_t number = threads_seen.fetch_add(1, std::memory_order_relaxed) + 1;
    return number;
  }
  // The grid cells this thread holds in this grid. A thread lets go of all
  // it holds after each attempt at a point, so when it comes to another grid
  // its list is empty and becomes that grid's.
  std::vector<int>& held_here() {
    thread_local std::vector<int> held;
    thread_local const OwnedLockGrid* grid = nullptr;
    if (grid != this) {
      DTM_CHECK(held.empty());
      grid = this;
    }
    return held;
  }

  bool try_lock_cell(int cell) {
    const uint32_t me = thread_number();
    std::atomic<uint32_t>& owner = owner_[cell];
    uint32_t now = owner.load(std::memory_order_relaxed);
    if (now == me) return true;
    if (now != 0 ||
        !owner.compare_exchange_strong(now, me, std::memory_order_acquire, std::memory_order_relaxed))
      return false;
    held_here().push_back(cell);
    return true;
  }

  int axis(double v, int a, double low) const {
    const int i = static_cast<int>((v - low) * scale_[a]);
    return i < 0 ? 0 : (i >= n_ ? n_ - 1 : i);
  }
  int index(int x, int y, int z) const { return (z * n_ + y) * n_ + x; }
  template <class P3>
  int grid_index(const P3& p) const {
    return index(axis(p.x(), 0, box_.xmin()), axis(p.y(), 1, box_.ymin()), axis(p.z(), 2, box_.zmin()));
  }

  CGAL::Bbox_3 box_;
  int n_;
  double scale_[3] = {};
  std::unique_ptr<std::atomic<uint32_t>[]> owner_;
};

}  // namespace dtm
