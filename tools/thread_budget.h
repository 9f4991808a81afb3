// The threads a tool's work uses (common/threads.h), with TBB held to the
// same number for as long as the budget lives: --threads N where the user
// gives it, else this process's share of the cores it was given (an MPI
// rank's share of its node: tools/mpi_session.h). Work never starts more
// threads than that, and a user who shares a machine can ask for fewer.
#pragma once

#include <oneapi/tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <optional>
#include <string>

#include "common/threads.h"

namespace dtm {

class ThreadBudget {
 public:
  // `asked`: --threads, 0 when not given; `share`: the process's share of
  // its cores; `lent`: the most threads its work may be lent for a while
  // (an MPI rank at work while the others on its node wait:
  // RankExchange::threads_while_busy()), TBB's limit.
  ThreadBudget(int asked, int share, int lent = 0) {
    asked = threads_allowed(asked);
    set_thread_count(asked > 0 ? asked : share);
    const int most = asked > 0 ? asked : std::max(share, lent);
    limit_.emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(most));
  }
  ~ThreadBudget() { set_thread_count(0); }
  ThreadBudget(const ThreadBudget&) = delete;
  ThreadBudget& operator=(const ThreadBudget&) = delete;

 private:
  std::optional<tbb::global_control> limit_;
};

// What the tool says where --threads asked for more than threads_allowed()
// (empty otherwise).
inline std::string threads_held_note(int asked) {
  if (asked <= threads_allowed(asked)) return {};
  return "--threads " + std::to_string(asked) + ": this process may run on " + std::to_string(cores_given()) +
         " cores; using " + std::to_string(threads_allowed(asked)) + " threads (more than " +
         std::to_string(kMostThreadsPerCore) + " a core only wait for each other)";
}

// The most --threads takes (threads_allowed() then holds it to the cores).
inline constexpr int kMostThreadsAsked = 4096;

inline void add_threads_option(CLI::App& app, int& threads) {
  app.add_option("--threads", threads,
                 "threads to use (default: the cores this process may run on, as taskset or a container "
                 "gives them; under mpirun, this rank's share of its node's)")
      ->check(CLI::Range(1, kMostThreadsAsked));
}

}  // namespace dtm
