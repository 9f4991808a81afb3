// Atomic updates of plain integers shared by the threads of a parallel_for:
// counts, cursors, minima and flags over arrays that are ordinary vectors the rest
// of the time. (std::atomic_ref would say the same; Debian's emscripten
// 3.1.6 libc++, the WebAssembly build's, lacks it. The compilers' builtins
// are what it is made of.)
#pragma once

#include <cstdint>

namespace dtm {

// x += v; returns x before. Relaxed: the callers join their threads before
// they read the results.
inline uint32_t atomic_fetch_add(uint32_t& x, uint32_t v) {
  return __atomic_fetch_add(&x, v, __ATOMIC_RELAXED);
}

// x = min(x, v).
inline void atomic_store_min(uint32_t& x, uint32_t v) {
  uint32_t seen = __atomic_load_n(&x, __ATOMIC_RELAXED);
  while (v < seen && !__atomic_compare_exchange_n(&x, &seen, v, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
}

// x |= v (bits of a word that other threads set bits of too).
inline void atomic_fetch_or(uint64_t& x, uint64_t v) { __atomic_fetch_or(&x, v, __ATOMIC_RELAXED); }

// x = v, where every thread that stores writes the same v (a mark).
inline void atomic_store(uint8_t& x, uint8_t v) { __atomic_store_n(&x, v, __ATOMIC_RELAXED); }

}  // namespace dtm
