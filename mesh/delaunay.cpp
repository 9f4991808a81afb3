#include "mesh/delaunay.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/Triangulation_cell_base_with_info_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <random>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <variant>

#include "common/first_touch.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"
#include "common/release.h"
#include "common/tbb_threads.h"
#include "common/threads.h"
#include "mesh/owned_lock_grid.h"

#ifdef CGAL_LINKED_WITH_TBB
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/scalable_allocator.h>
#include <oneapi/tbb/task_arena.h>
#endif

namespace dtm {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
// A cell's index in the last exported mesh; cells CGAL makes later start at -1.
struct CellTag {
  int32_t index = -1;
};
using Vb = CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>;
using Cb = CGAL::Triangulation_cell_base_with_info_3<CellTag, K, CGAL::Delaunay_triangulation_cell_base_3<K>>;
#ifdef CGAL_LINKED_WITH_TBB
// Large batches are inserted by TBB's threads, each locking the cells it
// changes; the cells do not depend on the order (docs/ARCHITECTURE.md §5).
// The locks never wait: CGAL's default grid (Tag_priority_blocking) has a
// thread spin, yielding, until a lower-priority holder lets go, and with
// more threads than cores the holder is the one not running
// (insert_sorted_in_parallel() says what that cost). A lock that is taken
// fails at once, and the inserting thread backs off (retry_backoff()); the
// grid is ours (mesh/owned_lock_grid.h), CGAL's non-blocking one spending
// a sixth of the insertion's time finding which locks a thread holds.
using Concurrency = CGAL::Parallel_tag;
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb, Concurrency>;
using DT = CGAL::Delaunay_triangulation_3<K, Tds, CGAL::Default, OwnedLockGrid>;
// A construction made on one thread (delaunay_tetrahedralize() given one:
// a block among others, a process on one core) takes CGAL's sequential
// type, whose cells need no lock and no concurrent container: 250k of
// bunny_1m's points went in 10-20% faster.
using SeqTds = CGAL::Triangulation_data_structure_3<Vb, Cb, CGAL::Sequential_tag>;
using SeqDT = CGAL::Delaunay_triangulation_3<K, SeqTds>;
#else
using Tds = CGAL::Triangulation_data_structure_3<Vb, Cb, CGAL::Sequential_tag>;
using DT = CGAL::Delaunay_triangulation_3<K, Tds>;
using SeqDT = DT;
#endif
// The small triangulations of cavity_fill stay sequential: a few dozen points.
using SmallTds = CGAL::Triangulation_data_structure_3<
    CGAL::Triangulation_vertex_base_with_info_3<uint32_t, K>,
    CGAL::Triangulation_cell_base_with_info_3<int32_t, K, CGAL::Delaunay_triangulation_cell_base_3<K>>>;
using SmallDT = CGAL::Delaunay_triangulation_3<K, SmallTds>;
using Point = K::Point_3;

// Batches this large go to every core; below, starting threads costs more
// than it gains.
constexpr size_t kParallelBatch = 20000;
// Below this many vertices the threads would contend for the same few cells.
constexpr size_t kParallelStart = 4096;

Point to_point(const GridPoint& p) { return Point(p.x, p.y, p.z); }

// With TBB, the triangulation's cells come from TBB's scalable allocator,
// which keeps what is freed in its own pools: a finished triangulation would
// stay in the process's memory through every later phase. Handed back here
// once a triangulation is gone (any triangulation: the pools a parallel
// one left are handed back after the next sequential one too). Not before
// the allocator has been used: asked to clean up with nothing from it yet,
// it crashed under ASan.
std::atomic<bool> tbb_allocator_used{false};
void release_freed_memory() {
#ifdef CGAL_LINKED_WITH_TBB
  if (tbb_allocator_used.load(std::memory_order_relaxed))
    scalable_allocation_command(TBBMALLOC_CLEAN_ALL_BUFFERS, nullptr);
#endif
}

// CGAL reports failures (a violated precondition, no memory) by exceptions;
// this door turns them into a Status, so that nothing above it throws.
template <class F>
Status guarded(F&& f) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    return {StatusCode::kLimitExceeded, "out of memory building a Delaunay tetrahedralization"};
  } catch (const std::exception& e) {
    return {StatusCode::kInternal, std::string("CGAL: ") + e.what()};
  }
}

// The number of finite cells: all of them but the hull's, which are the
// infinite vertex's. (CGAL's number_of_finite_cells() walks every cell, a
// pass over the whole triangulation's memory; this walks the hull.)
template <class Tri>
size_t finite_cell_count(const Tri& dt) {
  if (dt.dimension() < 3) return 0;
  size_t infinite = 0;
  dt.incident_cells(dt.infinite_vertex(), CGAL::Counting_output_iterator(&infinite));
  return dt.number_of_cells() - infinite;
}

// kLimitExceeded once the triangulation holds more cells than
// kMaxCellsPerVertex per vertex: checked every few insertions, so the excess
// it can allocate is bounded.
template <class Tri>
Status check_cells(const Tri& dt) {
  const size_t v = dt.number_of_vertices();
  if (dt.number_of_cells() <= kMaxCellsPerVertex * v + 4096) return Status::Ok();
  return {StatusCode::kLimitExceeded,
          "the Delaunay tetrahedralization of these points has over " + std::to_string(kMaxCellsPerVertex) +
              " cells per vertex (" + std::to_string(dt.number_of_cells()) + " cells for " +
              std::to_string(v) +
              " vertices): the points lie in a degenerate configuration such as two lines"};
}

// Inserts item_of(0), ..., item_of(n - 1) (point and id) in that order, each
// located from the previous one, with the cell check every 256 insertions.
template <class Tri, class ItemOf>
Status insert_in_order(Tri& dt, size_t n, ItemOf&& item_of) {
  typename Tri::Cell_handle hint;
  for (size_t i = 0; i < n; ++i) {
    const auto [point, id] = item_of(i);
    auto v = dt.insert(point, hint);
    v->info() = id;
    hint = v->cell();
    if ((i & 255) == 255) DTM_RETURN_IF_ERROR(check_cells(dt));
  }
  return check_cells(dt);
}

#ifdef CGAL_LINKED_WITH_TBB
// After a thread's `failures`-th failed attempt at a point (another thread
// holds some of its cells): a few yields, then sleeps of a random length
// that doubles up to about a millisecond. The holder may be a thread that
// is not running (more threads than cores, another process's); a retry at
// once would take the core it needs. Random, so that two threads that met
// do not meet again at once.
void retry_backoff(int failures) {
  if (failures <= 3) {
    std::this_thread::yield();
    return;
  }
  thread_local std::minstd_rand random(
      static_cast<uint32_t>(std::hash<std::thread::id>{}(std::this_thread::get_id())));
  const uint32_t longest = 2u << std::min(failures - 4, 9);  // microseconds: 2 .. 1024
  std::this_thread::sleep_for(std::chrono::microseconds(1 + random() % longest));
}

// CGAL's parallel range insertion (Delaunay_triangulation_3::insert_with_info)
// on points already in spatial order: each thread takes a run of
// consecutive points, each located from the thread's previous one, and
// retries a point whose cells another thread holds, backing off first.
// CGAL's own call would copy the slice and sort it again (a shuffle and a
// multiscale sort), and retries at once: with its blocking locks and no
// back-off, 300k points took 3.7 s on 2 threads on 2 cores and did not end
// in 120 s on 8 (an MPI rank per core's share, each with a pool the size of
// the node, is that case: docs/ARCHITECTURE.md §5.9); with neither, 3.4 s
// on 2 to 32 threads.
template <class Item>
void insert_sorted_in_parallel(DT& dt, std::span<const Item> items) {
  // Every thread starts from some vertex; then from its previous point.
  const DT::Vertex_handle start = dt.finite_vertices_begin();
  tbb::enumerable_thread_specific<DT::Vertex_handle> hints(start);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, items.size()), [&](const tbb::blocked_range<size_t>& r) {
    DT::Vertex_handle& hint = hints.local();
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const Point& p = items[i].first;
      for (int failures = 0;; retry_backoff(++failures)) {
        if (dt.try_lock_vertex(hint) && dt.try_lock_point(p)) {
          bool could_lock_zone = false;
          const DT::Vertex_handle v = dt.insert(p, hint, &could_lock_zone);
          dt.unlock_all_elements();
          if (could_lock_zone) {
            if (v != DT::Vertex_handle()) {
              v->info() = items[i].second;
              hint = v;
            }
            break;
          }
        } else {
          dt.unlock_all_elements();
        }
      }
    }
  });
}
#endif

// What CGAL's range insertion does (spatial sort, then insertion with the
// previous vertex as hint), plus the cell check. A large batch goes to
// every core in slices of at most an eighth of what the triangulation
// holds, with the check after each: in the sorted order (a multiscale
// Hilbert order of random samples) every slice is spread over the whole
// batch, so a degenerate configuration shows while its cells are still a
// fraction of the limit.
template <class Tri>
Status insert_batch(Tri& dt, std::span<const GridPoint> points, std::span<const uint32_t> ids) {
  DTM_CHECK(points.size() == ids.size());
  using Item = std::pair<Point, uint32_t>;
  std::vector<Item> batch;
  batch.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) batch.emplace_back(to_point(points[i]), ids[i]);
  using SortTraits = CGAL::Spatial_sort_traits_adapter_3<K, CGAL::First_of_pair_property_map<Item>>;
#ifdef CGAL_LINKED_WITH_TBB
  const int threads = thread_count();
  if constexpr (std::is_same_v<Tri, DT>) {
    if (batch.size() >= kParallelBatch && threads > 1 && !getenv("DTM_SEQ_DT")) {
      // TBB's threads, as many as the process was given (common/threads.h).
      tbb::task_arena arena(arena_threads());
      return arena.execute([&]() -> Status {
        CGAL::spatial_sort<CGAL::Parallel_tag>(batch.begin(), batch.end(), SortTraits());
        // The first points one by one, while the triangulation is small or flat:
        // the threads need a 3D triangulation to lock, with room for both.
        const size_t held = dt.number_of_vertices();
        size_t done = held >= kParallelStart ? 0 : std::min(batch.size(), kParallelStart - held);
        DTM_RETURN_IF_ERROR(insert_in_order(dt, done, [&](size_t i) { return batch[i]; }));
        for (; done < batch.size() && dt.dimension() < 3; ++done)
          DTM_RETURN_IF_ERROR(insert_in_order(dt, 1, [&](size_t) { return batch[done]; }));
        CGAL::Bbox_3 box;
        for (const GridPoint& p : points) box += to_point(p).bbox();
        for (auto v : dt.finite_vertex_handles()) box += v->point().bbox();
        typename DT::Lock_data_structure locks(box, 50);
        // The triangulation must not keep the locks past this scope, even when
        // CGAL throws (out of memory).
        struct Unlock {
          DT& dt;
          ~Unlock() { dt.set_lock_data_structure(nullptr); }
        } unlock{dt};
        dt.set_lock_data_structure(&locks);
        while (done < batch.size()) {
          const size_t slice =
              std::min(batch.size() - done, std::max<size_t>(kParallelStart, dt.number_of_vertices() / 8));
          insert_sorted_in_parallel(dt, std::span<const Item>(batch).subspan(done, slice));
          done += slice;
          DTM_RETURN_IF_ERROR(check_cells(dt));
        }
        return Status::Ok();
      });
    }
  }
#endif
  CGAL::spatial_sort(batch.begin(), batch.end(), SortTraits());
  return insert_in_order(dt, batch.size(), [&](size_t i) { return batch[i]; });
}

// A cell's vertex ids, ascending: its key in the canonical order.
std::array<uint32_t, 4> sorted_ids(std::array<uint32_t, 4> ids) {
  std::sort(ids.begin(), ids.end());
  return ids;
}
template <class Handle>
std::array<uint32_t, 4> sorted_ids(Handle c) {
  return sorted_ids({c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()});
}

// Which corner of a cell comes first, second, ...: identity for an export
// as built; for a canonical one, the smallest id first and the other three
// turned so that the smallest of them is second (an even permutation: the
// orientation stays positive). CGAL's cell holds its corners in some
// rotation that follows the order the points went in, which a parallel
// insertion varies; what is computed in floating point on a cell's corners
// in their order (a circumcentre, a triangle's distance) must not.
using Corners = std::array<int, 4>;
template <class Handle>
Corners canonical_corners(Handle c) {
  std::array<uint32_t, 4> id;
  for (int i = 0; i < 4; ++i) id[i] = c->vertex(i)->info();
  Corners p = {0, 1, 2, 3};
  const int m = static_cast<int>(std::min_element(id.begin(), id.end()) - id.begin());
  if (m != 0) {
    // Two swaps: the smallest to the front, and the two corners left alone.
    std::swap(p[0], p[m]);
    const int x = m == 1 ? 2 : 1, y = m == 3 ? 2 : 3;
    std::swap(p[x], p[y]);
  }
  if (id[p[2]] < id[p[1]] && id[p[2]] < id[p[3]])
    p = {p[0], p[2], p[3], p[1]};
  else if (id[p[3]] < id[p[1]] && id[p[3]] < id[p[2]])
    p = {p[0], p[3], p[1], p[2]};
  return p;
}
template <class Handle>
Corners corners_as_built(Handle) {
  return {0, 1, 2, 3};
}

// Writes cell c into out at index k, its corners in the order `p` gives.
template <class Handle>
void write_cell(Handle c, const Corners& p, TetMesh& out, size_t k) {
  for (int i = 0; i < 4; ++i) {
    out.cells[k][i] = c->vertex(p[i])->info();
    out.neighbors[k][i] = c->neighbor(p[i])->info().index;
  }
}

// Asks for what write_cell (and the corners' order) reads of a cell: its
// vertices' ids and its neighbours' tags, anywhere in memory. Asked for
// some cells ahead, a pass over the cells no longer waits on them: the
// export of bunny_1m's level 0 in the decoder took 1.1-1.7 s on 2 cores
// without, 0.5-0.9 s with (alternating runs).
template <class Handle>
void prefetch_corners(Handle c) {
  for (int i = 0; i < 4; ++i) {
    __builtin_prefetch(&c->vertex(i)->info());
    __builtin_prefetch(&c->neighbor(i)->info());
  }
}
// The same for a pass that reads only the cell's vertex ids.
template <class Handle>
void prefetch_vertex_ids(Handle c) {
  for (int i = 0; i < 4; ++i) __builtin_prefetch(&c->vertex(i)->info());
}
constexpr size_t kAhead = 8;

// The cells of `handles`, in that order, as vertex ids and neighbour tags
// (each handle's tag already set to its position, -1 for infinite cells),
// each cell's corners in the order corners_of gives.
template <class Handle, class CornersOf>
TetMesh cells_of(const std::vector<Handle>& handles, CornersOf corners_of, double spare = 0) {
  TetMesh out;
  const size_t m = handles.size();
  out.cells.reserve(m + static_cast<size_t>(spare * static_cast<double>(m)));
  out.neighbors.reserve(out.cells.capacity());
  resize_on_every_core(out.cells, m);
  resize_on_every_core(out.neighbors, m);
  constexpr size_t kBlock = 4096;
  parallel_for((m + kBlock - 1) / kBlock,
               [&](size_t block) {
                 const size_t end = std::min(m, block * kBlock + kBlock);
                 for (size_t k = block * kBlock; k < end; ++k) {
                   if (k + kAhead < end) prefetch_corners(handles[k + kAhead]);
                   write_cell(handles[k], corners_of(handles[k]), out, k);
                 }
               },
               2);
  return out;
}

// The finite cells in the order the triangulation holds them (after a
// parallel insertion, the threads' order: it varies from run to run), each
// cell's tag its index.
template <class Tri>
TetMesh export_as_built(Tri& dt, double spare) {
  using Handle = typename Tri::Cell_handle;
  if (dt.dimension() < 3) return {};
  std::vector<Handle> handles;
  handles.reserve(finite_cell_count(dt));
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) {
    c->info().index = dt.is_infinite(c) ? -1 : static_cast<int32_t>(handles.size());
    if (!dt.is_infinite(c)) handles.push_back(c);
  }
  return cells_of(handles, corners_as_built<Handle>, spare);
}

// The finite cells in the canonical order (topology.h: by their sorted vertex
// ids), each one's corners turned by canonical_corners, whatever order the
// triangulation holds them in (after a parallel insertion, the threads'
// order): everything computed from an exported mesh is then the same on
// every run. The cells are grouped by their smallest
// vertex as CGAL lists them (a counting sort), each vertex's few sorted on
// every core, and written out in that order. Each cell's tag becomes its
// index; `previous`, if given, receives each cell's tag before (-1: new).
template <class Tri>
TetMesh export_mesh(Tri& dt, std::vector<int32_t>* previous, double spare = 0) {
  using Handle = typename Tri::Cell_handle;
  if (previous) previous->clear();
  if (dt.dimension() < 3) return {};
  const size_t m = finite_cell_count(dt);
  uint32_t top = 0;
  for (auto v : dt.finite_vertex_handles()) top = std::max(top, v->info());
  std::vector<uint32_t> start(size_t{top} + 2, 0);
  auto smallest = [](Handle c) {
    return std::min({c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()});
  };
  constexpr size_t kBlock = 4096;
  // The handles in one walk of the container (its blocks in memory order:
  // quick), each one's smallest corner on every core (four vertices
  // anywhere in memory: the slow part, which took 1.4 s on one core at
  // bunny_1m's level 0), then the counting sort by them.
  std::vector<Handle> found;
  found.reserve(m);
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) {
    if (dt.is_infinite(c))
      c->info().index = -1;
    else
      found.push_back(c);
  }
  std::vector<uint32_t> least;
  resize_on_every_core(least, found.size());
  parallel_ranges(found.size(), kBlock, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) {
      if (k + kAhead < last) prefetch_corners(found[k + kAhead]);
      least[k] = smallest(found[k]);
    }
  });
  for (uint32_t v : least) ++start[v + 1];
  for (size_t v = 1; v < start.size(); ++v) start[v] += start[v - 1];
  std::vector<Handle> handles(m);
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t k = 0; k < found.size(); ++k) handles[fill[least[k]]++] = found[k];
  }
  release(found);
  release(least);
  // Each group's keys are read once into a small buffer and sorted there:
  // comparing through the handles would chase four vertex pointers per
  // comparison (this sort was a tenth of the encoder's time).
  using Keyed = std::pair<std::array<uint32_t, 4>, Handle>;
  parallel_for((start.size() - 1 + kBlock - 1) / kBlock,
               [&](size_t block) {
                 std::vector<Keyed> group;
                 for (size_t v = block * kBlock; v < std::min(start.size() - 1, block * kBlock + kBlock);
                      ++v) {
                   group.clear();
                   for (uint32_t k = start[v]; k < start[v + 1]; ++k)
                     group.emplace_back(sorted_ids(handles[k]), handles[k]);
                   // Keys are distinct (no two cells share four vertices).
                   std::sort(group.begin(), group.end(),
                             [](const Keyed& a, const Keyed& b) { return a.first < b.first; });
                   for (size_t i = 0; i < group.size(); ++i) handles[start[v] + i] = group[i].second;
                 }
               },
               2);
  // Each cell is its own thread's alone: the tags are written in parallel.
  if (previous) resize_on_every_core(*previous, m);
  parallel_for((m + kBlock - 1) / kBlock,
               [&](size_t block) {
                 for (size_t k = block * kBlock; k < std::min(m, block * kBlock + kBlock); ++k) {
                   if (previous) (*previous)[k] = handles[k]->info().index;
                   handles[k]->info().index = static_cast<int32_t>(k);
                 }
               },
               2);
  return cells_of(handles, canonical_corners<Handle>, spare);
}

// The canonical export again after local edits, given `before`, the last
// export (its cells and neighbours as returned). The cells the edits left
// keep their tags, the index they had in `before`, and their order; only the
// cells made since are read and sorted, and the two sorted runs are merged:
// the result is export_mesh's, at the cost of a pass over the arrays, and
// of less memory than a whole export (no handle per cell).
template <class Tri>
TetMesh export_patched(Tri& dt, const TetMesh& before, std::vector<int32_t>& previous) {
  using Handle = typename Tri::Cell_handle;
  const size_t old_count = before.cells.size();
  // One walk of the triangulation: the cells of `before` that are left
  // (their handles, by tag), and the new ones by their keys.
  using Keyed = std::pair<std::array<uint32_t, 4>, Handle>;
  std::vector<Handle> handle_of_old(old_count);  // a null handle: gone
  std::vector<Handle> fresh;
  for (auto c : dt.finite_cell_handles()) {
    const int32_t tag = c->info().index;
    if (tag >= 0) {
      DTM_CHECK(static_cast<size_t>(tag) < old_count && handle_of_old[static_cast<size_t>(tag)] == nullptr);
      handle_of_old[static_cast<size_t>(tag)] = c;
    } else {
      fresh.push_back(c);
    }
  }
  // The new cells' keys (their corners anywhere in memory) on every core;
  // the keys are distinct, so any sort gives the one order.
  std::vector<Keyed> made(fresh.size());
  parallel_ranges(fresh.size(), 4096, [&](size_t first, size_t last) {
    for (size_t j = first; j < last; ++j) {
      if (j + kAhead < last) prefetch_corners(fresh[j + kAhead]);
      made[j] = {sorted_ids(fresh[j]), fresh[j]};
    }
  });
  release(fresh);
  dtm::parallel_sort(made.begin(), made.end(),
                     [](const Keyed& a, const Keyed& b) { return a.first < b.first; });

  // The merge of the two key orders, on every core: each range of old
  // cells knows how many kept cells come before it (a prefix sum of the
  // ranges' counts) and where its keys fall among the new ones, so it
  // writes its kept cells, and the new ones whose keys fall before its
  // last, at their final places. Every tag is final after it; the old
  // cells next to something new (or to the hull) are kept to read their
  // neighbours from.
  const size_t m = finite_cell_count(dt);
  TetMesh out;
  resize_on_every_core(out.cells, m);
  resize_on_every_core(out.neighbors, m);
  assign_on_every_core(previous, m, -1);
  std::vector<int32_t> new_of_old;
  assign_on_every_core(new_of_old, old_count, -1);
  constexpr size_t kRange = 16384;
  const size_t ranges = (old_count + kRange - 1) / kRange;
  std::vector<size_t> kept_before(ranges + 1, 0);
  parallel_ranges(old_count, kRange, [&](size_t first, size_t last) {
    kept_before[first / kRange + 1] = static_cast<size_t>(std::count_if(
        handle_of_old.begin() + static_cast<std::ptrdiff_t>(first),
        handle_of_old.begin() + static_cast<std::ptrdiff_t>(last), [](Handle h) { return h != nullptr; }));
  });
  for (size_t r = 0; r < ranges; ++r) kept_before[r + 1] += kept_before[r];
  DTM_CHECK(kept_before[ranges] + made.size() == m);
  const auto first_made_from = [&](size_t i) {  // the first new cell whose key is not below old cell i's
    if (i == old_count) return made.size();
    const std::array<uint32_t, 4> key = sorted_ids(before.cells[i]);
    return static_cast<size_t>(std::lower_bound(made.begin(), made.end(), key,
                                                [](const Keyed& a, const auto& k) { return a.first < k; }) -
                               made.begin());
  };
  auto place_made = [&](size_t j, size_t kept) {
    const size_t k = kept + j;
    const Handle c = made[j].second;
    const Corners p = canonical_corners(c);
    for (int f = 0; f < 4; ++f) out.cells[k][f] = c->vertex(p[f])->info();
    c->info().index = static_cast<int32_t>(k);
  };
  std::vector<std::vector<Handle>> bordering(std::max<size_t>(ranges, 1));
  parallel_ranges(old_count, kRange, [&](size_t first, size_t last) {
    size_t kept = kept_before[first / kRange];
    size_t j = first == 0 ? 0 : first_made_from(first);
    for (size_t i = first; i < last; ++i) {
      const Handle c = handle_of_old[i];
      if (c == nullptr) continue;
      const std::array<uint32_t, 4> key = sorted_ids(before.cells[i]);
      for (; j < made.size() && made[j].first < key; ++j) place_made(j, kept);
      const size_t k = kept++ + j;
      out.cells[k] = before.cells[i];
      previous[k] = static_cast<int32_t>(i);
      new_of_old[i] = static_cast<int32_t>(k);
      c->info().index = static_cast<int32_t>(k);
      for (int32_t n : before.neighbors[i])
        if (n < 0 || handle_of_old[static_cast<size_t>(n)] == nullptr) {
          bordering[first / kRange].push_back(c);
          break;
        }
    }
    for (const size_t end = first_made_from(last); j < end; ++j) place_made(j, kept);
  });
  if (old_count == 0)
    for (size_t j = 0; j < made.size(); ++j) place_made(j, 0);
  // Neighbours: a kept cell's are as before where they were kept too; the
  // rest are read.
  parallel_ranges(m, 4096, [&](size_t first, size_t last) {
    for (size_t at = first; at < last; ++at) {
      if (previous[at] < 0) continue;
      const auto i = static_cast<size_t>(previous[at]);
      for (int f = 0; f < 4; ++f) {
        const int32_t n = before.neighbors[i][f];
        out.neighbors[at][f] = n >= 0 ? new_of_old[static_cast<size_t>(n)] : -1;
      }
    }
  });
  // (An old cell's corners in `before` are in the canonical rotation too,
  // which is a function of the cell alone.)
  // Every tag is final: each cell writes its own row, on every core.
  parallel_ranges(made.size(), 4096, [&](size_t first, size_t last) {
    for (size_t j = first; j < last; ++j) {
      const Handle c = made[j].second;
      write_cell(c, canonical_corners(c), out, static_cast<size_t>(c->info().index));
    }
  });
  parallel_for(bordering.size(), [&](size_t r) {
    for (Handle c : bordering[r])
      write_cell(c, canonical_corners(c), out, static_cast<size_t>(c->info().index));
  });
  return out;
}

// delaunay_tetrahedralize without the release of the freed memory.
template <class Tri>
StatusOr<TetMesh> tetrahedralize_in(std::span<const GridPoint> points) {
  std::vector<uint32_t> ids(points.size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<uint32_t>(i);
  Tri dt;
  DTM_RETURN_IF_ERROR(guarded([&] { return insert_batch(dt, points, ids); }));
  if (dt.number_of_vertices() != points.size())
    return Status{StatusCode::kInvalidInput, "the points to tetrahedralize are not distinct"};
  if (dt.dimension() < 3)
    return Status{StatusCode::kInvalidInput,
                  "the " + std::to_string(points.size()) + " points span only " +
                      std::to_string(std::max(dt.dimension(), 0)) +
                      " dimension(s); a tetrahedral mesh needs 4 points not in one plane"};
  return export_mesh(dt, nullptr);
}

template <class Tri>
std::vector<std::array<uint32_t, 4>> finite_cells_of(const Tri& dt) {
  using Handle = typename Tri::Cell_handle;
  std::vector<std::array<uint32_t, 4>> out;
  if (dt.dimension() < 3) return out;
  // The handles in one walk of the container (quick: its blocks in memory
  // order), their corners read on every core (four vertices anywhere in
  // memory: the slow part, 0.15-0.2 s on one core at bunny_1m's level 1,
  // which the decoder's layer candidates wait for).
  std::vector<Handle> handles;
  handles.reserve(finite_cell_count(dt));
  for (auto c : dt.finite_cell_handles()) handles.push_back(c);
  resize_on_every_core(out, handles.size());
  parallel_ranges(handles.size(), 4096, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) {
      if (k + kAhead < last) prefetch_vertex_ids(handles[k + kAhead]);
      const Handle c = handles[k];
      out[k] = {c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()};
    }
  });
  return out;
}

}  // namespace

StatusOr<TetMesh> delaunay_tetrahedralize(std::span<const GridPoint> points) {
  // One thread (at this call: a block's share may grow later) inserts
  // into the sequential type; the cells, and so the export, are the same.
  const bool sequential = thread_count() == 1 || points.size() < kParallelBatch;
  if (!sequential) tbb_allocator_used = true;
  StatusOr<TetMesh> out = sequential ? tetrahedralize_in<SeqDT>(points) : tetrahedralize_in<DT>(points);
  release_freed_memory();
  return out;
}

bool parallel_delaunay_available() {
#ifdef CGAL_LINKED_WITH_TBB
  return true;
#else
  return false;
#endif
}

// Made on one thread (a block among others, a process on one core), the
// triangulation is CGAL's sequential type, as delaunay_tetrahedralize()'s
// is: its insertions stay on one thread, whatever the thread count later.
struct IncrementalDelaunay::Impl {
#ifdef CGAL_LINKED_WITH_TBB
  using Held = std::variant<DT, SeqDT>;
#else
  using Held = std::variant<DT>;  // DT is the sequential type
#endif
  Held dt;
  // Made in place: a parallel triangulation made first and then replaced
  // would have taken its first cells from TBB's allocator.
  explicit Impl(bool sequential) : dt(made(sequential)) {}
  static Held made(bool sequential) {
    if (sequential) return Held(std::in_place_type<SeqDT>);
    tbb_allocator_used = true;
    return Held(std::in_place_type<DT>);
  }
  template <class F>
  decltype(auto) with(F&& f) {
    return std::visit(std::forward<F>(f), dt);
  }
  template <class F>
  decltype(auto) with(F&& f) const {
    return std::visit(std::forward<F>(f), dt);
  }
};

IncrementalDelaunay::IncrementalDelaunay() : impl_(std::make_unique<Impl>(thread_count() == 1)) {}
IncrementalDelaunay::~IncrementalDelaunay() {
  impl_.reset();
  release_freed_memory();
}

bool IncrementalDelaunay::parallel() const {
  return !std::is_same_v<DT, SeqDT> && std::holds_alternative<DT>(impl_->dt);
}

Status IncrementalDelaunay::insert(std::span<const GridPoint> points, std::span<const uint32_t> ids) {
  return guarded([&] { return impl_->with([&](auto& dt) { return insert_batch(dt, points, ids); }); });
}

Status IncrementalDelaunay::insert_one_by_one(std::span<const GridPoint> points,
                                              std::span<const uint32_t> ids) {
  DTM_CHECK(points.size() == ids.size());
  return guarded([&] {
    return impl_->with([&](auto& dt) {
      return insert_in_order(dt, points.size(),
                             [&](size_t i) { return std::make_pair(to_point(points[i]), ids[i]); });
    });
  });
}

Status IncrementalDelaunay::remove(std::span<const GridPoint> points) {
  return guarded([&] {
    return impl_->with([&](auto& dt) {
      for (const GridPoint& p : points) {
        typename std::remove_reference_t<decltype(dt)>::Vertex_handle v;
        if (!dt.is_vertex(to_point(p), v))
          return Status{StatusCode::kInvalidInput, "remove: a point is not a vertex"};
        dt.remove(v);
      }
      return Status::Ok();
    });
  });
}

int IncrementalDelaunay::dimension() const {
  return impl_->with([](const auto& dt) { return dt.dimension(); });
}
size_t IncrementalDelaunay::number_of_vertices() const {
  return impl_->with([](const auto& dt) { return dt.number_of_vertices(); });
}
TetMesh IncrementalDelaunay::mesh(CellOrder order, double spare) const {
  return impl_->with([&](auto& dt) {
    return order == CellOrder::kCanonical ? export_mesh(dt, nullptr, spare) : export_as_built(dt, spare);
  });
}
std::vector<std::array<uint32_t, 4>> IncrementalDelaunay::finite_cells() const {
  return impl_->with([](const auto& dt) { return finite_cells_of(dt); });
}

TetMesh IncrementalDelaunay::mesh(std::vector<int32_t>& previous_index) {
  return impl_->with([&](auto& dt) { return export_mesh(dt, &previous_index); });
}
TetMesh IncrementalDelaunay::mesh(const TetMesh& before, std::vector<int32_t>& previous_index) {
  return impl_->with([&](auto& dt) {
    return before.cells.empty() ? export_mesh(dt, &previous_index)
                                : export_patched(dt, before, previous_index);
  });
}

CavityFill cavity_fill(std::span<const GridPoint> link, std::span<const uint32_t> link_ids,
                       const GridPoint& apex) {
  CavityFill out;
  SmallDT dt;
  SmallDT::Cell_handle hint;
  for (size_t i = 0; i < link.size(); ++i) {
    auto v = dt.insert(to_point(link[i]), hint);
    v->info() = link_ids[i];
    hint = v->cell();
  }
  if (dt.dimension() < 3) return out;
  const Point q = to_point(apex);
  SmallDT::Locate_type lt;
  int li, lj;
  const SmallDT::Cell_handle start = dt.locate(q, lt, li, lj, hint);
  DTM_CHECK(lt != SmallDT::VERTEX);
  std::vector<SmallDT::Cell_handle> conflicts;
  dt.find_conflicts(q, start, CGAL::Emptyset_iterator(), std::back_inserter(conflicts));
  for (auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) c->info() = -1;
  for (SmallDT::Cell_handle c : conflicts)
    if (!dt.is_infinite(c)) {
      c->info() = static_cast<int32_t>(out.cells.size());
      out.cells.push_back(
          {c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()});
    }
  out.neighbors.resize(out.cells.size());
  for (SmallDT::Cell_handle c : conflicts)
    if (c->info() >= 0)
      for (int i = 0; i < 4; ++i) out.neighbors[c->info()][i] = c->neighbor(i)->info();
  return out;
}

}  // namespace dtm
