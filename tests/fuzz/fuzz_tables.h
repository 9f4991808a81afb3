// A table as a stream frames it (codec/stream/table_framing.h: u32 length,
// body, XXH3-64), made from a fuzz input below the checksum that keeps the
// stream targets from reaching a damaged one: bytes 1-2 of the input give the
// body's length n (little-endian, at most what follows), the n bytes after
// them are the body. The table targets (field table, regions, cell values)
// share it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "common/checksum.h"

struct FuzzTable {
  std::vector<uint8_t> table;      // framed
  std::span<const uint8_t> after;  // the input's bytes after the body
};

// `size` >= 3.
inline FuzzTable fuzz_table(const uint8_t* data, size_t size) {
  const size_t body = std::min<size_t>(data[1] | size_t{data[2]} << 8, size - 3);
  FuzzTable out;
  out.table.resize(4 + body + 8);
  for (int k = 0; k < 4; ++k) out.table[k] = static_cast<uint8_t>(body >> (8 * k));
  std::copy_n(data + 3, body, out.table.begin() + 4);
  const uint64_t checksum = dtm::xxh3_64(std::span(out.table).first(4 + body));
  for (int k = 0; k < 8; ++k) out.table[4 + body + k] = static_cast<uint8_t>(checksum >> (8 * k));
  out.after = std::span(data + 3 + body, size - 3 - body);
  return out;
}
