// The threads a TBB arena of this process's work takes: thread_count()
// (common/threads.h), but no more than TBB's own limit, a
// tbb::global_control the program set (the tools' ThreadBudget, Python's
// set_threads()) or else the machine's. An arena wider than that limit
// starts no more workers, and TBB writes a warning on standard error.
#pragma once

#ifdef CGAL_LINKED_WITH_TBB
#include <oneapi/tbb/global_control.h>

#include <algorithm>
#include <climits>

#include "common/threads.h"

namespace dtm {

inline int arena_threads() {
  const size_t most = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  return std::max(1, std::min(thread_count(), static_cast<int>(std::min<size_t>(most, INT_MAX))));
}

}  // namespace dtm
#endif
