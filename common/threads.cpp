#include "common/threads.h"

#include <algorithm>
#include <atomic>
#include <thread>

#if defined(__linux__) && !defined(__EMSCRIPTEN__)
#include <sched.h>
#endif

namespace dtm {
namespace {

std::atomic<int> chosen{0};        // 0: cores_given()
thread_local int fixed_share = 0;  // 0: none (ThreadShare)
// A ThreadShares piece's share, when the innermost share the thread holds is one.
thread_local const std::atomic<int>* growing = nullptr;

}  // namespace

int cores_given() {
#ifdef __EMSCRIPTEN__
  return 1;  // one decoder per WebAssembly worker, built without threads
#else
#if defined(__linux__)
  cpu_set_t mask;
  if (sched_getaffinity(0, sizeof mask, &mask) == 0) return std::max(1, CPU_COUNT(&mask));
#endif
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
#endif
}

int thread_count() {
  if (growing) return std::max(1, growing->load(std::memory_order_relaxed));
  if (fixed_share > 0) return fixed_share;
  const int n = chosen.load(std::memory_order_relaxed);
  return n > 0 ? n : cores_given();
}

void set_thread_count(int n) { chosen.store(std::max(0, n), std::memory_order_relaxed); }

ThreadShare::ThreadShare(int n) : before_(fixed_share), before_growing_(growing) {
  fixed_share = std::max(1, n);
  growing = nullptr;
}
ThreadShare::~ThreadShare() {
  fixed_share = before_;
  growing = before_growing_;
}

ThreadShares::ThreadShares(int threads, int pieces)
    : threads_(std::make_unique<std::atomic<int>[]>(static_cast<size_t>(std::max(1, pieces)))),
      pieces_(static_cast<size_t>(std::max(1, pieces))),
      total_(std::max(1, threads)) {
  const int n = static_cast<int>(pieces_);
  for (int k = 0; k < n; ++k)
    threads_[static_cast<size_t>(k)] = std::max(1, total_ / n + (k < total_ % n ? 1 : 0));
}

int ThreadShares::share(int piece) const {
  return threads_[static_cast<size_t>(piece)].load(std::memory_order_relaxed);
}

void ThreadShares::end(int piece) {
  const std::lock_guard<std::mutex> lock(handing_over_);
  threads_[static_cast<size_t>(piece)] = 0;
  // The threads no piece at work holds (none where there are more pieces
  // than threads, each holding one) go to the one holding the fewest.
  int held = 0;
  size_t fewest = pieces_;
  for (size_t j = 0; j < pieces_; ++j) {
    const int n = threads_[j];
    if (n == 0) continue;  // ended
    held += n;
    if (fewest == pieces_ || n < threads_[fewest]) fewest = j;
  }
  if (fewest < pieces_ && held < total_) threads_[fewest] += total_ - held;
}

ThreadShares::Use::Use(ThreadShares& shares, int piece)
    : shares_(shares), piece_(piece), before_(fixed_share), before_growing_(growing) {
  fixed_share = 0;
  growing = &shares.threads_[static_cast<size_t>(piece)];
}

ThreadShares::Use::~Use() {
  fixed_share = before_;
  growing = before_growing_;
  shares_.end(piece_);
}

}  // namespace dtm
