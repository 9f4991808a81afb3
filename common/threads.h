// How many threads this process's work may use. By default the cores it was
// given: those of its affinity mask (taskset, an MPI launcher's binding, a
// container's cpuset), not every core of the machine. A program may say
// otherwise (meshenc --threads, an MPI rank's share of its node,
// tools/thread_budget.h). parallel_for() and the Delaunay door's TBB arenas
// (mesh/delaunay.cpp) read it, so that no part of the work starts more
// threads than it was given: threads beyond the cores only wait for each
// other (docs/ARCHITECTURE.md §5.9).
#pragma once

namespace dtm {

// The cores in this process's affinity mask (at least 1; 1 in WebAssembly).
int cores_given();

// The threads the work uses: set_thread_count()'s, else cores_given().
int thread_count();
// n >= 1 sets it for the whole process; n <= 0 goes back to cores_given().
void set_thread_count(int n);

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
};

}  // namespace dtm
