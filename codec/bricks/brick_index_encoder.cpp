#include "codec/bricks/brick_index_encoder.h"

namespace dtm {
namespace {

void put_varint(std::vector<uint8_t>& out, uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<uint8_t>(v | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<uint8_t>(v));
}

}  // namespace

std::vector<uint8_t> write_brick_index(std::span<const BrickChunk> chunks, IndexFields fields) {
  std::vector<uint8_t> out;
  put_varint(out, chunks.size());
  for (size_t i = 0; i < chunks.size(); ++i) {
    const BrickChunk& c = chunks[i];
    put_varint(out, i == 0 ? c.brick : c.brick - chunks[i - 1].brick - 1);
    put_varint(out, c.new_points);
    put_varint(out, c.payload_bytes);
    put_varint(out, c.carving_bytes);
    put_varint(out, c.value_bytes);
    if (fields.regions) put_varint(out, c.region_bytes);
    if (fields.faces) put_varint(out, c.face_bytes);
    if (fields.cell_values) put_varint(out, c.cell_value_bytes);
    for (int b = 0; b < 4; ++b) out.push_back(static_cast<uint8_t>(c.checksum >> (8 * b)));
    if (fields.cell_values)
      for (int b = 0; b < 4; ++b) out.push_back(static_cast<uint8_t>(c.cell_value_checksum >> (8 * b)));
  }
  return out;
}

}  // namespace dtm
