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
  const int n = chosen.load(std::memory_order_relaxed);
  return n > 0 ? n : cores_given();
}

void set_thread_count(int n) { chosen.store(std::max(0, n), std::memory_order_relaxed); }

}  // namespace dtm
