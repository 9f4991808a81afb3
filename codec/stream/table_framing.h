// The framing of the tables between the stream header and its first layer
// (the field table, spec/FORMAT.md §2.1; the region and face tag tables,
// §2.2-2.3): a u32 length, the body, then XXH3-64 of both. Written and
// read here once for every table.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/byte_io.h"
#include "common/checksum.h"
#include "common/status.h"

namespace dtm {

inline std::vector<uint8_t> frame_table(std::span<const uint8_t> body) {
  ByteWriter w;
  w.u32(static_cast<uint32_t>(body.size()));
  w.bytes(body);
  w.u64(xxh3_64(w.data()));
  return w.take();
}

// The body of the table `name` at the start of `bytes`, and the table's
// whole size. kNeedMoreInput until it is all there (nothing is allocated
// for it before); kCorrupt when its length is 0 or above `max_body`, or its
// checksum differs.
inline Status unframe_table(std::span<const uint8_t> bytes, uint32_t max_body, const std::string& name,
                            std::span<const uint8_t>& body, size_t& consumed) {
  ByteReader head(bytes);
  uint32_t table_bytes = 0;
  if (!head.u32(table_bytes)) return {StatusCode::kNeedMoreInput, name + " incomplete"};
  if (table_bytes == 0 || table_bytes > max_body) return corrupt(name + ": its length is out of range");
  const size_t whole = 4 + size_t{table_bytes} + 8;
  if (bytes.size() < whole) return {StatusCode::kNeedMoreInput, name + " incomplete"};
  ByteReader tail(bytes.subspan(whole - 8, 8));
  uint64_t checksum = 0;
  tail.u64(checksum);
  if (checksum != xxh3_64(bytes.first(whole - 8))) return corrupt(name + ": checksum mismatch");
  body = bytes.subspan(4, table_bytes);
  consumed = whole;
  return Status::Ok();
}

}  // namespace dtm
