// Runs independent work on the cores the process was given
// (common/threads.h; one thread in a WebAssembly build).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

#include "common/threads.h"

namespace dtm {

// The threads a loop below starts: thread_count(), at most kMostLoopThreads.
// (Until 2026-12-03 at most 8, which left half of a 16-core machine idle in
// every loop; the bound now only keeps `--threads 4096` from starting
// thousands of threads a loop.)
inline constexpr size_t kMostLoopThreads = 256;
inline size_t loop_threads() {
  return std::clamp<size_t>(static_cast<size_t>(thread_count()), 1, kMostLoopThreads);
}

// Runs body(i) for i in [0, n), each once, on thread_count() threads. body(0) runs
// first, alone: a CGAL tree builds its search structures on its first
// query, after which it is read-only and safe to share. The others are
// handed out in runs of consecutive items, each thread taking the next run
// when it is done with its last (about kRunsPerThread runs a thread), so
// that items of uneven cost, and cores that another process slows, leave no
// thread waiting long on the others; the calling thread works too. Below
// `serial_below` items it all runs on the calling thread (starting threads
// costs more than the work).
inline constexpr size_t kRunsPerThread = 16;
template <typename Body>
void parallel_for(size_t n, const Body& body, size_t serial_below = 2) {
  if (n == 0) return;
  body(0);
  const size_t threads = std::min(loop_threads(), n - 1);
  if (threads <= 1 || n < serial_below) {
    for (size_t i = 1; i < n; ++i) body(i);
    return;
  }
  const size_t run = std::max<size_t>(1, (n - 1) / (threads * kRunsPerThread));
  std::atomic<size_t> next{1};
  const auto work = [&] {
    for (size_t first; (first = next.fetch_add(run, std::memory_order_relaxed)) < n;)
      for (size_t i = first, last = std::min(n, first + run); i < last; ++i) body(i);
  };
  std::vector<std::thread> workers;
  workers.reserve(threads - 1);
  for (size_t t = 1; t < threads; ++t) workers.emplace_back(work);
  work();
  for (auto& w : workers) w.join();
}

// Runs body(part, parts) once for each part in [0, parts), parts being the
// threads (loop_threads()), all at once: for a pass that each thread makes in
// full, doing its share of it (the rows of a range of vertices, say),
// where parallel_for's first item alone would keep the others waiting.
template <typename Body>
void on_every_thread(const Body& body) {
  const size_t parts = loop_threads();
  std::vector<std::thread> workers;
  for (size_t part = 1; part < parts; ++part) workers.emplace_back([&, part] { body(part, parts); });
  body(size_t{0}, parts);
  for (auto& w : workers) w.join();
}

// Runs body(k) for each k in [0, n), each once, on at most n threads of
// loop_threads() (the calling one too), handing the items out one at a
// time: for a few items of much work each (a layer's value components),
// where parallel_for's first item alone would keep the others waiting. An
// exception an item throws is thrown again once every item is done (the
// lowest item's).
template <typename Body>
void for_each_item(size_t n, const Body& body) {
  const size_t threads = std::min(loop_threads(), n);
  std::vector<std::exception_ptr> failed(n);
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t k; (k = next.fetch_add(1, std::memory_order_relaxed)) < n;) try {
        body(k);
      } catch (...) {
        failed[k] = std::current_exception();
      }
  };
  std::vector<std::thread> workers;
  for (size_t t = 1; t < threads; ++t) workers.emplace_back(work);
  work();
  for (auto& w : workers) w.join();
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
}

// Runs body(first, last) on consecutive ranges of at most `block` of [0, n),
// on every core.
template <typename Body>
void parallel_ranges(size_t n, size_t block, const Body& body) {
  parallel_for((n + block - 1) / block, [&](size_t b) { body(b * block, std::min(n, b * block + block)); },
               2);
}

// What a loop over [0, n) in order would append to one vector, made on every
// core: body(first, last, out) appends a range's items to its own `out`;
// the ranges' vectors are joined in order.
template <typename T, typename Body>
std::vector<T> collect_in_order(size_t n, size_t block, const Body& body) {
  std::vector<std::vector<T>> parts((n + block - 1) / block);
  parallel_ranges(n, block, [&](size_t first, size_t last) { body(first, last, parts[first / block]); });
  size_t total = 0;
  for (const auto& p : parts) total += p.size();
  std::vector<T> out;
  out.reserve(total);
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

}  // namespace dtm
