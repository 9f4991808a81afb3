// A bricked layer's chunks, written (spec/FORMAT.md §3.5): the encoder's side
// of bricks.h; chunk_decoder.cpp reads them.
#include <algorithm>
#include <vector>

#include "codec/bricks/bricks.h"

namespace dtm {

int choose_brick_depth(std::span<const MortonCode> codes, int qbits, uint64_t target) {
  int best = 0;
  for (int depth = 1; depth <= std::min(qbits, kMaxBrickDepth); ++depth) {
    uint64_t bricks = 0, previous = UINT64_MAX;
    for (const MortonCode c : codes) {
      const uint64_t b = brick_of(c, qbits, depth);
      bricks += b != previous;
      previous = b;
    }
    if (bricks == 0 || codes.size() < target * bricks) break;
    best = depth;
  }
  return best;
}

std::vector<uint8_t> encode_chunk_points(std::span<const GridPoint> points, std::span<const MortonCode> known,
                                         uint64_t brick, int qbits, int depth,
                                         const SetCoderModels& after_base) {
  const std::span<const MortonCode> inside = known_in_brick(known, brick, qbits, depth);
  SetCoderModels models = chunk_models(after_base, inside, qbits);
  return encode_point_set(inside, points, qbits, models, brick_node(brick, qbits, depth));
}

std::vector<BrickChunk> write_chunks(std::span<const BrickParts> parts, std::vector<uint8_t>& chunk_bytes) {
  std::vector<BrickChunk> chunks;
  for (const BrickParts& p : parts) {
    BrickChunk chunk;
    chunk.brick = p.brick;
    chunk.new_points = p.new_points;
    chunk.payload_bytes = static_cast<uint32_t>(p.payload.size());
    chunk.carving_bytes = static_cast<uint32_t>(p.carving.size());
    chunk.value_bytes = static_cast<uint32_t>(p.values.size());
    chunk.region_bytes = static_cast<uint32_t>(p.regions.size());
    chunk.face_bytes = static_cast<uint32_t>(p.faces.size());
    chunk.cell_value_bytes = static_cast<uint32_t>(p.cell_values.size());
    if (chunk.size() == 0) continue;
    const size_t start = chunk_bytes.size();
    chunk_bytes.insert(chunk_bytes.end(), p.payload.begin(), p.payload.end());
    chunk_bytes.insert(chunk_bytes.end(), p.carving.begin(), p.carving.end());
    chunk_bytes.insert(chunk_bytes.end(), p.values.begin(), p.values.end());
    chunk_bytes.insert(chunk_bytes.end(), p.regions.begin(), p.regions.end());
    chunk_bytes.insert(chunk_bytes.end(), p.faces.begin(), p.faces.end());
    chunk.checksum = chunk_checksum(std::span(chunk_bytes).subspan(start));
    chunk_bytes.insert(chunk_bytes.end(), p.cell_values.begin(), p.cell_values.end());
    if (!p.cell_values.empty()) chunk.cell_value_checksum = chunk_checksum(p.cell_values);
    chunks.push_back(chunk);
  }
  return chunks;
}

}  // namespace dtm
