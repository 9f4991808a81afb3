// A bricked layer's points, decoded (spec/FORMAT.md §3.5); the encoder's
// side is codec/bricked_layer_encoder.cpp.
#include <string>

#include "codec/bricks.h"
#include "common/parallel_for.h"

namespace dtm {

Status check_chunk(const BrickChunk& chunk, std::span<const uint8_t> bytes) {
  if (chunk_checksum(bytes) != chunk.checksum)
    return {StatusCode::kCorrupt, "brick " + std::to_string(chunk.brick) + ": chunk checksum mismatch"};
  return Status::Ok();
}

Status decode_chunk_points(const BrickChunk& chunk, std::span<const uint8_t> payload,
                           std::span<const MortonCode> known, int qbits, int depth,
                           const SetCoderModels& after_base, std::vector<GridPoint>& out) {
  if (chunk.new_points == 0) return Status::Ok();
  const std::span<const MortonCode> inside = known_in_brick(known, chunk.brick, qbits, depth);
  SetCoderModels models = chunk_models(after_base, inside, qbits);
  return decode_point_set(payload, inside, qbits, chunk.new_points, models, out,
                          brick_node(chunk.brick, qbits, depth))
      .with_context("brick " + std::to_string(chunk.brick));
}

Status decode_bricked_points(std::span<const ChunkInput> chunks, std::span<const MortonCode> known, int qbits,
                             int depth, SetCoderModels& models, std::vector<GridPoint>& out) {
  for (const ChunkInput& c : chunks) DTM_RETURN_IF_ERROR(check_chunk(*c.chunk, c.bytes));
  if (known.empty()) {  // the base layer: one chunk, depth 0, the stream's models
    for (const ChunkInput& c : chunks)
      DTM_RETURN_IF_ERROR(decode_point_set(split_chunk(*c.chunk, c.bytes).payload, {}, qbits,
                                           c.chunk->new_points, models, out,
                                           brick_node(c.chunk->brick, qbits, depth)));
    return Status::Ok();
  }
  // Each chunk into its own list (its size as decoded, never as claimed).
  std::vector<std::vector<GridPoint>> decoded(chunks.size());
  std::vector<Status> status(chunks.size());
  parallel_for(
      chunks.size(),
      [&](size_t i) {
        const ChunkInput& c = chunks[i];
        status[i] = decode_chunk_points(*c.chunk, split_chunk(*c.chunk, c.bytes).payload, known, qbits, depth,
                                        models, decoded[i]);
      },
      2);
  for (const Status& s : status) DTM_RETURN_IF_ERROR(s);
  for (auto& d : decoded) out.insert(out.end(), d.begin(), d.end());
  return Status::Ok();
}

}  // namespace dtm
