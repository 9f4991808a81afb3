#include "common/checksum.h"

// The state type is public only with XXH_STATIC_LINKING_ONLY: it lets the
// state live on the stack.
#define XXH_STATIC_LINKING_ONLY
#include <xxhash.h>

namespace dtm {

uint64_t xxh3_64(std::span<const uint8_t> bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

uint64_t xxh3_64(std::span<const uint8_t> bytes, uint64_t seed) {
  return XXH3_64bits_withSeed(bytes.data(), bytes.size(), seed);
}

uint64_t xxh3_64(std::span<const uint8_t> first, std::span<const uint8_t> second) {
  // The streaming state lives on the stack: no allocation that could fail.
  XXH3_state_t state;
  XXH3_INITSTATE(&state);
  XXH3_64bits_reset(&state);
  XXH3_64bits_update(&state, first.data(), first.size());
  XXH3_64bits_update(&state, second.data(), second.size());
  return XXH3_64bits_digest(&state);
}

}  // namespace dtm
