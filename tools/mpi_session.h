// MPI, where the build has it (CMake finds an MPI library: meshdec links it
// and defines DTM_WITH_MPI) and the process was started by mpirun: then the
// tool is one rank of many. Started alone, or built without MPI, it is rank 0
// of 1 and never calls MPI (no MPI start-up cost, no MPI messages).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/exchange.h"
#include "common/threads.h"

#ifdef DTM_WITH_MPI
#include <mpi.h>

#include "tools/mpi_answers.h"
#ifdef __linux__
#include <sched.h>
#endif
#endif

namespace dtm {

class MpiSession : public RankExchange {
 public:
  MpiSession(int* argc, char*** argv) {
#ifdef DTM_WITH_MPI
    // Open MPI's and MPICH's (PMI) launchers say so in the environment.
    if (std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK")) {
      // DTM_MPI_ONE_THREAD=1 asks for what an MPI without threads gives
      // (the ranks then answer each other in their exchanges): tested.
      const int wanted = std::getenv("DTM_MPI_ONE_THREAD") ? MPI_THREAD_FUNNELED : MPI_THREAD_MULTIPLE;
      int provided = MPI_THREAD_SINGLE;
      MPI_Init_thread(argc, argv, wanted, &provided);
      threads_ = provided >= MPI_THREAD_MULTIPLE;
      active_ = true;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
      MPI_Comm_size(MPI_COMM_WORLD, &size_);
      find_node();
    }
#else
    (void)argc, (void)argv;
#endif
  }
  ~MpiSession() override {
#ifdef DTM_WITH_MPI
    if (active_) MPI_Finalize();
#endif
  }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  // The threads this rank's share of its cores allows: the cores of its
  // affinity mask over the ranks on its node whose masks meet it (with
  // `--bind-to none` every rank has the node's cores: each gets 1/P of
  // them; bound to a core, each its core); cores_given() when alone.
  int cores_share() const { return cores_share_ > 0 ? cores_share_ : cores_given(); }
  // The most threads threads_while_busy() gives this rank: the cores it may
  // run on (TBB's limit; the work itself starts thread_count()).
  int cores_lent_at_most() const {
    return active_ && lend_ ? std::max(cores_share(), mask_cores_) : cores_share();
  }
  // Off: a rank keeps to its share (the user gave --threads).
  void lend_cores(bool on) { lend_ = on; }
  // RankExchange: the cores this rank shares with others over those of
  // them at work: while the rest of its node's ranks only wait (a level
  // of fewer blocks than ranks), a rank at work takes their cores.
  int threads_while_busy(std::span<const uint8_t> busy) const override {
    const int share = thread_count();
    if (!active_ || !lend_) return share;
    int working = 0;
    for (int r : neighbours_) working += r < static_cast<int>(busy.size()) && busy[static_cast<size_t>(r)];
    return std::max(share, mask_cores_ / std::max(1, working));
  }
  // RankExchange: MPI_Allgatherv of every rank's bytes (at most 2 GiB from
  // one rank at a time: MPI counts are ints).
  std::vector<std::vector<uint8_t>> all_gather(std::span<const uint8_t> mine) override {
    std::vector<size_t> sizes;
    const std::vector<uint8_t> all = all_gather_joined(mine, 1, &sizes);
    std::vector<std::vector<uint8_t>> out(sizes.size());
    size_t at = 0;
    for (size_t r = 0; r < sizes.size(); ++r) {
      out[r].assign(all.begin() + static_cast<std::ptrdiff_t>(at),
                    all.begin() + static_cast<std::ptrdiff_t>(at + sizes[r]));
      at += sizes[r];
    }
    return out;
  }
  // The same, every rank's bytes joined in rank order in one buffer (no
  // copy a rank), `sizes` (if given) each rank's count. Counted in elements
  // of `element_bytes` (MPI's counts and offsets are ints): up to 2^31 of
  // them in all, 48 GiB of 24-byte points.
  std::vector<uint8_t> all_gather_joined(std::span<const uint8_t> mine, size_t element_bytes = 1,
                                         std::vector<size_t>* sizes = nullptr) const {
    std::vector<uint8_t> all;
    gather_joined(
        mine, element_bytes,
        [&](size_t elements) {
          all.resize(elements * element_bytes);
          return all.data();
        },
        sizes);
    return all;
  }
  // The same of values (trivially copyable), gathered into the vector
  // returned: no second copy of them all to convert the bytes.
  template <class T>
  std::vector<T> all_gather_of(std::span<const T> mine) const {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<T> all;
    gather_joined(
        {reinterpret_cast<const uint8_t*>(mine.data()), mine.size_bytes()}, sizeof(T),
        [&](size_t elements) {
          all.resize(elements);
          return reinterpret_cast<uint8_t*>(all.data());
        },
        nullptr);
    return all;
  }
  // Every rank's pieces_to[r] go to rank r, each piece `piece` values
  // (trivially copyable) but the last; returns what the ranks sent this
  // one, joined in rank order, each rank's pieces in order. Sent a piece to
  // each rank at a time, each freed once sent, and received into a part
  // per rank joined at the end, each part freed once joined: a rank holds
  // about what it sends or what it receives, not both (a TetGen .ele's
  // tetrahedra, sent to the ranks that hold them, are most of the memory
  // of reading it).
  template <class T>
  std::vector<T> all_to_all_in_pieces(std::vector<std::vector<std::vector<T>>> pieces_to,
                                      size_t piece) const {
    static_assert(std::is_trivially_copyable_v<T>);
    if (piece == 0 || piece * sizeof(T) > static_cast<size_t>(INT32_MAX))
      throw std::logic_error("MPI: a piece of no values or over 2 GiB");
    for (const auto& pieces : pieces_to)
      for (size_t k = 0; k + 1 < pieces.size(); ++k)
        if (pieces[k].size() != piece) throw std::logic_error("MPI: a piece short of its size");
#ifdef DTM_WITH_MPI
    if (active_) {
      const auto n = static_cast<size_t>(size_);
      if (pieces_to.size() != n) throw std::logic_error("MPI: pieces for another number of ranks");
      // How many values each rank sends this one, and in how many pieces.
      std::vector<uint64_t> sending(n, 0), coming(n, 0);
      for (size_t r = 0; r < n; ++r)
        for (const auto& p : pieces_to[r]) sending[r] += p.size();
      MPI_Request request = MPI_REQUEST_NULL;
      MPI_Ialltoall(sending.data(), 1, MPI_UINT64_T, coming.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD,
                    &request);
      wait_for(request);
      // A receiver sizes each piece by its own `piece`: every rank's must
      // be the same (said on every rank, so that none waits in vain).
      uint64_t sizes[2] = {piece, ~uint64_t { piece }};  // the largest, and the smallest
      MPI_Iallreduce(MPI_IN_PLACE, sizes, 2, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD, &request);
      wait_for(request);
      if (sizes[0] != ~sizes[1]) throw std::runtime_error("MPI: the ranks' pieces differ in size");
      const auto pieces_of = [piece](uint64_t values) {
        return static_cast<size_t>((values + piece - 1) / piece);
      };
      uint64_t rounds = 0;
      for (size_t r = 0; r < n; ++r)
        rounds = std::max<uint64_t>(rounds, std::max(pieces_of(sending[r]), pieces_of(coming[r])));
      MPI_Iallreduce(MPI_IN_PLACE, &rounds, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD, &request);
      wait_for(request);
      std::vector<std::vector<T>> from(n);
      for (size_t r = 0; r < n; ++r) from[r].reserve(coming[r]);  // room, not memory, until received
      std::vector<std::vector<T>> landing(n);
      std::vector<MPI_Request> requests(2 * n, MPI_REQUEST_NULL);
      constexpr int kTag = 8;
      for (size_t k = 0; k < rounds; ++k) {
        for (size_t r = 0; r < n; ++r) {
          const uint64_t left = coming[r] - std::min<uint64_t>(coming[r], k * piece);
          if (left > 0) {
            landing[r].resize(static_cast<size_t>(std::min<uint64_t>(left, piece)));
            MPI_Irecv(landing[r].data(), static_cast<int>(landing[r].size() * sizeof(T)), MPI_BYTE,
                      static_cast<int>(r), kTag, MPI_COMM_WORLD, &requests[r]);
          }
          if (k < pieces_to[r].size() && !pieces_to[r][k].empty())
            MPI_Isend(pieces_to[r][k].data(), static_cast<int>(pieces_to[r][k].size() * sizeof(T)), MPI_BYTE,
                      static_cast<int>(r), kTag, MPI_COMM_WORLD, &requests[n + r]);
        }
        for (MPI_Request& q : requests)
          if (q != MPI_REQUEST_NULL) wait_for(q);
        for (size_t r = 0; r < n; ++r) {
          if (k * piece < coming[r]) from[r].insert(from[r].end(), landing[r].begin(), landing[r].end());
          if (k < pieces_to[r].size()) std::vector<T>().swap(pieces_to[r][k]);
        }
      }
      uint64_t total = 0;
      for (uint64_t c : coming) total += c;
      std::vector<T> all;
      all.reserve(total);
      for (auto& part : from) {
        all.insert(all.end(), part.begin(), part.end());
        std::vector<T>().swap(part);
      }
      return all;
    }
#endif
    std::vector<T> all;
    for (auto& pieces : pieces_to)
      for (auto& p : pieces) {
        all.insert(all.end(), p.begin(), p.end());
        std::vector<T>().swap(p);
      }
    return all;
  }
  // A thread that answers the other ranks, where MPI lets several threads
  // call it (MPI_THREAD_MULTIPLE); else nullptr.
  std::unique_ptr<RankAnswers> answer_while_working(const Answerer& answer) override {
#ifdef DTM_WITH_MPI
    if (active_ && threads_ && size_ > 1) return std::make_unique<MpiAnswers>(MPI_COMM_WORLD, answer);
#endif
    (void)answer;
    return nullptr;
  }
  // Whether `ok` holds on every rank.
  bool all(bool ok) const {
#ifdef DTM_WITH_MPI
    if (active_) {
      int mine = ok ? 1 : 0, every = 0;
      MPI_Request request = MPI_REQUEST_NULL;
      MPI_Iallreduce(&mine, &every, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD, &request);
      wait_for(request);
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
      MPI_Request request = MPI_REQUEST_NULL;
      MPI_Iallreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD, &request);
      wait_for(request);
      return total;
    }
#endif
    return v;
  }

 private:
  // all_gather_joined()'s work: every rank's elements gathered at
  // room(total elements), in rank order.
  void gather_joined(std::span<const uint8_t> mine, size_t element_bytes,
                     const std::function<uint8_t*(size_t)>& room, std::vector<size_t>* sizes) const {
    const size_t elements = mine.size() / element_bytes;
    if (elements * element_bytes != mine.size()) throw std::logic_error("MPI: not whole elements");
#ifdef DTM_WITH_MPI
    if (active_) {
      if (elements > static_cast<size_t>(INT32_MAX))
        throw std::runtime_error("MPI: over 2^31 elements from one rank");
      const int count = static_cast<int>(elements);
      std::vector<int> counts(static_cast<size_t>(size_)), offsets(static_cast<size_t>(size_), 0);
      MPI_Request request = MPI_REQUEST_NULL;
      MPI_Iallgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD, &request);
      wait_for(request);
      size_t total = 0;
      for (int r = 0; r < size_; ++r) {
        if (total > static_cast<size_t>(INT32_MAX))
          throw std::runtime_error("MPI: over 2^31 elements gathered");
        offsets[static_cast<size_t>(r)] = static_cast<int>(total);
        total += static_cast<size_t>(counts[static_cast<size_t>(r)]);
      }
      if (total > static_cast<size_t>(INT32_MAX))
        throw std::runtime_error("MPI: over 2^31 elements gathered");
      MPI_Datatype type = MPI_BYTE;
      if (element_bytes > 1) {
        MPI_Type_contiguous(static_cast<int>(element_bytes), MPI_BYTE, &type);
        MPI_Type_commit(&type);
      }
      uint8_t* all = room(total);
      MPI_Iallgatherv(mine.data(), count, type, all, counts.data(), offsets.data(), type, MPI_COMM_WORLD,
                      &request);
      wait_for(request);
      if (element_bytes > 1) MPI_Type_free(&type);
      if (sizes) {
        sizes->resize(counts.size());
        for (size_t r = 0; r < counts.size(); ++r)
          (*sizes)[r] = static_cast<size_t>(counts[r]) * element_bytes;
      }
      return;
    }
#endif
    if (elements > 0)
      std::memcpy(room(elements), mine.data(), mine.size());
    else
      room(0);
    if (sizes) *sizes = {mine.size()};
  }
#ifdef DTM_WITH_MPI
  // This rank's share of its node's cores, and the ranks it shares them
  // with.
  void find_node() {
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    int ranks = 1;
    MPI_Comm_size(node, &ranks);
    std::vector<int> world(static_cast<size_t>(ranks));
    MPI_Allgather(&rank_, 1, MPI_INT, world.data(), 1, MPI_INT, node);
    mask_cores_ = cores_given();
    int share = cores_given() / std::max(1, ranks);
    neighbours_ = world;
#ifdef __linux__
    cpu_set_t mine;
    CPU_ZERO(&mine);
    if (sched_getaffinity(0, sizeof mine, &mine) != 0)
      for (int c = 0; c < cores_given(); ++c) CPU_SET(c, &mine);
    std::vector<cpu_set_t> all(static_cast<size_t>(ranks));
    MPI_Allgather(&mine, sizeof mine, MPI_BYTE, all.data(), sizeof mine, MPI_BYTE, node);
    neighbours_.clear();
    for (int r = 0; r < ranks; ++r) {
      cpu_set_t both;
      CPU_AND(&both, &mine, &all[static_cast<size_t>(r)]);
      if (CPU_COUNT(&both) > 0) neighbours_.push_back(world[static_cast<size_t>(r)]);
    }
    mask_cores_ = CPU_COUNT(&mine);
    share = mask_cores_ / std::max<int>(1, static_cast<int>(neighbours_.size()));
#endif
    MPI_Comm_free(&node);
    cores_share_ = std::max(1, share);
  }
#endif

  int cores_share_ = 0;
  int mask_cores_ = 0;           // the cores this rank may run on
  std::vector<int> neighbours_;  // the ranks (this one too) whose cores meet this one's
  bool lend_ = true;             // threads_while_busy() lends the idle ranks' cores
  bool active_ = false;
  bool threads_ = false;  // MPI_THREAD_MULTIPLE
  int rank_ = 0;
  int size_ = 1;
};

// The one session of the process (made in main, before the options are read).
MpiSession& mpi_session();

}  // namespace dtm
