// Grows a big array with its new pages first touched on every core.
//
// The kernel zeroes a page of fresh memory when a thread first touches it,
// on that thread. std::vector's resize value-initializes its new elements
// on the calling thread, so it faults every new page there while the other
// cores wait, though the array is then written on all of them. At
// bunny_1m's level 0 the meshes' cells and neighbours (208 MB), the cells
// around each vertex (90 MB) and the like: with them grown here, meshenc's
// page faults while no other thread ran fell from 1.04 s to 0.39 s of
// samples (perf at 400 Hz, 2026-12-03).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "common/parallel_for.h"

namespace dtm {

// Below this many new bytes the faults cost less than starting threads.
inline constexpr size_t kFirstTouchInParallelFrom = size_t{8} << 20;

// The pages of [first, first + bytes) made present (zero-filled where they
// were not), on every core: each thread asks the kernel for its own
// contiguous part (MADV_POPULATE_WRITE, Linux 5.14 on; it writes nothing,
// so bytes already there are kept) or, where the kernel cannot, writes
// zeros over it. For storage that holds no object yet.
inline void touch_on_every_core(void* first, size_t bytes) {
  // The parts meet on 2 MiB boundaries, so that no two threads fault one
  // transparent huge page (the tools ask glibc for them:
  // tools/huge_pages.h). Offsets from `first`, rounded by the addresses
  // they stand for.
  constexpr uintptr_t kPage = 4096, kHugePage = uintptr_t{2} << 20;
  auto* const base = static_cast<std::byte*>(first);
  const auto address = reinterpret_cast<uintptr_t>(first);
  const auto down = [address](size_t offset, uintptr_t unit) -> size_t {
    const uintptr_t at = (address + offset) & ~(unit - 1);
    return at > address ? at - address : 0;
  };
  on_every_thread([&](size_t part, size_t parts) {
    const auto cut = [&](size_t k) -> size_t {
      if (k == parts) return bytes;
      return k == 0 ? 0 : std::min(bytes, down(bytes / parts * k, kHugePage));
    };
    const size_t lo = cut(part), hi = cut(part + 1);
    if (hi <= lo) return;
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    // madvise takes whole pages: the partial pages at the ends are left to
    // whoever writes them.
    const size_t a = down(lo + kPage - 1, kPage), b = down(hi, kPage);
    if (b <= a || madvise(base + a, b - a, MADV_POPULATE_WRITE) == 0) return;
#endif
    std::memset(base + lo, 0, hi - lo);
  });
}

// v.resize(n) (the new elements value-initialized: zeros), the new pages
// first touched on every core. For arrays of plain values (cells, ids,
// flags) that are then written on every core.
template <class T, class Allocator>
void resize_on_every_core(std::vector<T, Allocator>& v, size_t n) {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_default_constructible_v<T>,
                "pages are touched as raw storage");
  if (n > v.size() && (n - v.size()) * sizeof(T) >= kFirstTouchInParallelFrom) {
    if (v.capacity() < n) v.reserve(n);
    // The storage past size() is allocated and holds no object yet.
    touch_on_every_core(static_cast<void*>(v.data() + v.size()), (n - v.size()) * sizeof(T));
  }
  v.resize(n);  // now a memset of present pages
}

// v.assign(n, value), the pages first touched and the values written on
// every core.
template <class T, class Allocator>
void assign_on_every_core(std::vector<T, Allocator>& v, size_t n, const T& value) {
  v.clear();
  resize_on_every_core(v, n);
  if (value == T{}) return;
  parallel_ranges(n, size_t{1} << 16, [&](size_t first, size_t last) {
    std::fill(v.begin() + static_cast<std::ptrdiff_t>(first), v.begin() + static_cast<std::ptrdiff_t>(last),
              value);
  });
}

}  // namespace dtm
