// How many threads this process's work may use. By default the cores it was
// given: those of its affinity mask (taskset, an MPI launcher's binding, a
// container's cpuset), not every core of the machine. A program may say
// otherwise (meshenc --threads, an MPI rank's share of its node,
// tools/thread_budget.h). parallel_for() and the Delaunay door's TBB arenas
// (mesh/delaunay.cpp) read it, so that no part of the work starts more
// threads than it was given: threads beyond the cores only wait for each
// other (docs/ARCHITECTURE.md §5.9).
#pragma once

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>

namespace dtm {

// The cores in this process's affinity mask (at least 1; 1 in WebAssembly).
int cores_given();

// The threads the work uses: set_thread_count()'s, else cores_given().
int thread_count();
// n >= 1 sets it for the whole process, as asked (a program holds a user's
// count to threads_allowed() first, as the tools do); n <= 0 goes back to
// cores_given(). TBB's arenas take no more than TBB's own limit either
// (common/tbb_threads.h): a program that wants more TBB threads than the
// machine's cores sets a tbb::global_control as well.
void set_thread_count(int n);

// Threads beyond a few a core only wait for each other, and each parallel
// loop starts its own: --threads 4096 made bunny_10k's bricked encoding
// take 118 s against 0.85 s (256: 10 s; 8 on 2 cores: 0.83 s against
// 0.63 s). The tools and Python's set_threads() hold a count asked above
// kMostThreadsPerCore a core of those this process may run on to that (the
// tools say so); set_thread_count() takes what it is given (tests ask for
// more on purpose).
inline constexpr int kMostThreadsPerCore = 4;
inline int threads_allowed(int asked) { return std::min(asked, kMostThreadsPerCore * cores_given()); }

// While it lives, the work the calling thread starts uses n threads
// (n >= 1): for two pieces of work run side by side, each on its share of
// the threads, so that together they start no more than thread_count().
class ThreadShare {
 public:
  explicit ThreadShare(int n);
  ~ThreadShare();
  ThreadShare(const ThreadShare&) = delete;
  ThreadShare& operator=(const ThreadShare&) = delete;

 private:
  int before_;
  const std::atomic<int>* before_growing_;
};

// `threads` split among `pieces` of work run side by side (a level's blocks,
// the stream writer's two sides), as evenly as they go and at least one
// each. A piece's share is read afresh at each parallel call its work makes,
// and when a piece ends, the threads no piece at work holds go to the one
// holding the fewest: the last pieces running take the cores of those done,
// instead of keeping their first share while those cores idle. The shares
// at work never add up to more than `threads` (or one each).
class ThreadShares {
 public:
  ThreadShares(int threads, int pieces);
  ThreadShares(const ThreadShares&) = delete;
  ThreadShares& operator=(const ThreadShares&) = delete;

  // While it lives, the work the calling thread starts uses piece k's
  // share; when it ends, piece k is done and its threads go on.
  class Use {
   public:
    Use(ThreadShares& shares, int piece);
    ~Use();
    Use(const Use&) = delete;
    Use& operator=(const Use&) = delete;

   private:
    ThreadShares& shares_;
    int piece_;
    int before_;
    const std::atomic<int>* before_growing_;
  };

  // Piece k's share now (0 once it has ended).
  int share(int piece) const;
  // Piece k has ended, or will not run: its threads go on (Use's end calls it).
  void end(int piece);

 private:
  std::mutex handing_over_;
  std::unique_ptr<std::atomic<int>[]> threads_;  // per piece: at least 1 while it works, 0 once it has ended
  size_t pieces_;
  int total_;
};

}  // namespace dtm
