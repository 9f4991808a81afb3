// MPI, where the build has it (CMake finds an MPI library: meshdec links it
// and defines DTM_WITH_MPI) and the process was started by mpirun: then the
// tool is one rank of many. Started alone, or built without MPI, it is rank 0
// of 1 and never calls MPI (no MPI start-up cost, no MPI messages).
#pragma once

#include <cstdint>
#include <cstdlib>

#ifdef DTM_WITH_MPI
#include <mpi.h>
#endif

namespace dtm {

class MpiSession {
 public:
  MpiSession(int* argc, char*** argv) {
#ifdef DTM_WITH_MPI
    // Open MPI's and MPICH's (PMI) launchers say so in the environment.
    if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK")) {
      MPI_Init(argc, argv);
      active_ = true;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
      MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
#else
    (void)argc, (void)argv;
#endif
  }
  ~MpiSession() {
#ifdef DTM_WITH_MPI
    if (active_) MPI_Finalize();
#endif
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // Whether `ok` holds on every rank.
  bool all(bool ok) const {
#ifdef DTM_WITH_MPI
    if (active_) {
      int mine = ok ? 1 : 0, every = 0;
      MPI_Allreduce(&mine, &every, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
      return every == 1;
    }
#endif
    return ok;
  }
  // The sum of `v` over the ranks.
  uint64_t sum(uint64_t v) const {
#ifdef DTM_WITH_MPI
    if (active_) {
      unsigned long long mine = v, total = 0;
      MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
      return total;
    }
#endif
    return v;
  }

 private:
  bool active_ = false;
  int rank_ = 0;
  int size_ = 1;
};

// The one session of the process (made in main, before the options are read).
MpiSession& mpi_session();

}  // namespace dtm
