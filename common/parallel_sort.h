// A sort on the cores the process was given (common/threads.h): TBB's where
// the build has it (not in WebAssembly), std::sort otherwise. The order is
// the comparison's, as std::sort's: callers sort keys that are distinct, or
// whose equal ones are alike, so that any run gives the same sequence.
#pragma once

#include <algorithm>

#include "common/threads.h"

#ifdef CGAL_LINKED_WITH_TBB
#include <oneapi/tbb/parallel_sort.h>
#include <oneapi/tbb/task_arena.h>

#include "common/tbb_threads.h"
#endif

namespace dtm {

template <typename It, typename Less>
void parallel_sort(It first, It last, const Less& less) {
#ifdef CGAL_LINKED_WITH_TBB
  // Below some ten thousand items a thread costs more than it saves.
  const int threads = thread_count();
  if (threads > 1 && last - first >= 16384) {
    tbb::task_arena(arena_threads()).execute([&] { tbb::parallel_sort(first, last, less); });
    return;
  }
#endif
  std::sort(first, last, less);
}

template <typename It>
void parallel_sort(It first, It last) {
  parallel_sort(first, last, std::less<>());
}

}  // namespace dtm
