// A bricked layer's points and values, decoded (spec/FORMAT.md §3.5): the
// decoder's side of bricks.h; chunk_encoder.cpp writes them.
#include <algorithm>
#include <string>

#include "codec/bricks/bricks.h"
#include "common/parallel_for.h"

namespace dtm {

Status check_chunk(const BrickChunk& chunk, std::span<const uint8_t> bytes, uint64_t at) {
  const std::string where =
      "brick " + std::to_string(chunk.brick) + ", its chunk at byte " + std::to_string(at);
  const uint64_t head = chunk.points_size();
  if (bytes.size() < head || chunk_checksum(bytes.first(head)) != chunk.checksum)
    return {StatusCode::kCorrupt, where + ": chunk checksum mismatch"};
  if (bytes.size() > head && chunk_checksum(bytes.subspan(head)) != chunk.cell_value_checksum)
    return {StatusCode::kCorrupt, where + ": the chunk's cell values' checksum mismatch (at byte " +
                                      std::to_string(at + head) + ")"};
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
  for (const ChunkInput& c : chunks) DTM_RETURN_IF_ERROR(check_chunk(*c.chunk, c.bytes, c.at));
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

Status decode_bricked_values(std::span<const ChunkInput> chunks, int qbits, int depth,
                             std::span<const FieldDescription> fields,
                             std::span<const GridPoint> known_points,
                             std::span<const FieldValues> known_values, std::span<const GridPoint> added,
                             std::vector<FieldValues>& out) {
  // The known points in Morton order (a chunk's, in its brick, are a run).
  std::vector<std::pair<MortonCode, uint32_t>> by_code(known_points.size());
  for (uint32_t v = 0; v < known_points.size(); ++v) by_code[v] = {morton_encode(known_points[v], qbits), v};
  std::sort(by_code.begin(), by_code.end());
  std::vector<size_t> first(chunks.size() + 1, 0);
  for (size_t i = 0; i < chunks.size(); ++i) first[i + 1] = first[i] + chunks[i].chunk->new_points;
  if (first.back() != added.size())
    return {StatusCode::kInternal, "decode_bricked_values: points and chunks differ"};
  std::vector<std::vector<FieldValues>> decoded(chunks.size());
  std::vector<Status> status(chunks.size());
  parallel_for(
      chunks.size(),
      [&](size_t i) {
        const BrickChunk& c = *chunks[i].chunk;
        if (c.new_points == 0) return;
        const int shift = 3 * (qbits - depth);
        const MortonCode lo = MortonCode{c.brick} << shift, hi = MortonCode{c.brick + 1} << shift;
        auto it = std::lower_bound(by_code.begin(), by_code.end(), std::pair<MortonCode, uint32_t>{lo, 0});
        std::vector<GridPoint> known;
        std::vector<std::vector<uint64_t>> known_bits(fields.size());
        for (; it != by_code.end() && it->first < hi; ++it) {
          known.push_back(known_points[it->second]);
          for (size_t f = 0; f < fields.size(); ++f) {
            const size_t n = static_cast<size_t>(fields[f].components);
            const auto& bits = known_values[f].bits;
            known_bits[f].insert(known_bits[f].end(),
                                 bits.begin() + static_cast<std::ptrdiff_t>(it->second * n),
                                 bits.begin() + static_cast<std::ptrdiff_t>((it->second + 1) * n));
          }
        }
        status[i] = decode_chunk_values(fields, split_chunk(c, chunks[i].bytes).values, known, known_bits,
                                        added.subspan(first[i], c.new_points), decoded[i])
                        .with_context("brick " + std::to_string(c.brick));
      },
      2);
  for (const Status& s : status) DTM_RETURN_IF_ERROR(s);
  out.clear();
  for (const FieldDescription& f : fields) out.push_back({f, {}});
  for (const auto& chunk : decoded)
    for (size_t f = 0; f < chunk.size(); ++f)
      out[f].bits.insert(out[f].bits.end(), chunk[f].bits.begin(), chunk[f].bits.end());
  return Status::Ok();
}

}  // namespace dtm
