// A bricked layer's index, written (the encoder library: parse_brick_index,
// bricks.h, reads it).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/bricks/bricks.h"

namespace dtm {

// The index: varint chunk count, then per chunk varint (brick - previous
// brick - 1; the first: brick), new_points, payload_bytes, carving_bytes,
// value_bytes, region_bytes, face_bytes and cell_value_bytes where `fields` says, the
// u32 checksum, and with cell_value_bytes the u32 cell_value_checksum.
// Offsets are not stored.
std::vector<uint8_t> write_brick_index(std::span<const BrickChunk> chunks, IndexFields fields);

}  // namespace dtm
