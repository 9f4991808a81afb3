#include "common/threads.h"

#include <algorithm>
#include <atomic>
#include <thread>

#if defined(__linux__) && !defined(__EMSCRIPTEN__)
#include <sched.h>
#endif

namespace dtm {
namespace {

std::atomic<int> chosen{0};  // 0: cores_given()
thread_local int share = 0;  // 0: none (ThreadShare)

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
  if (share > 0) return share;
  const int n = chosen.load(std::memory_order_relaxed);
  return n > 0 ? n : cores_given();
}

void set_thread_count(int n) { chosen.store(std::max(0, n), std::memory_order_relaxed); }

ThreadShare::ThreadShare(int n) : before_(share) { share = std::max(1, n); }
ThreadShare::~ThreadShare() { share = before_; }

}  // namespace dtm
