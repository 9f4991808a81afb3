#include "checksum.h"

#include <xxhash.h>

namespace dtm {

uint64_t xxh3_64(std::span<const uint8_t> bytes) { return XXH3_64bits(bytes.data(), bytes.size()); }

}  // namespace dtm
