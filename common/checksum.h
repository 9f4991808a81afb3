// XXH3-64 (libxxhash): the checksum of headers and layers, and the hash of a
// level's canonical cell set.
#pragma once

#include <cstdint>
#include <span>

namespace dtm {

uint64_t xxh3_64(std::span<const uint8_t> bytes);
uint64_t xxh3_64(std::span<const uint8_t> bytes, uint64_t seed);
// XXH3-64 of `first` followed by `second`, without joining them in memory.
uint64_t xxh3_64(std::span<const uint8_t> first, std::span<const uint8_t> second);

}  // namespace dtm
