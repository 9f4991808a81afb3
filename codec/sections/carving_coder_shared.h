// What the carving coder's encoder (carving_encoder.cpp) and decoder
// (carving_decoder.cpp) share: the traversal both sides make, one bit a
// cell, and the chunks' coding order (spec/FORMAT.md §3.2, §3.5). Both
// sides must visit the cells identically; it is written here once.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "bitstream/range_coder.h"
#include "codec/sections/carving_coder.h"

namespace dtm {

// The traversal both sides make: the cells in canonical order, one bit
// each (1 = alpha's verdict is wrong), coded by `code_bit(model, cell)`
// (the encoder's writes the bit it knows, the decoder's reads it); `kept`
// starts as alpha's verdicts and ends as the true ones.
template <class CodeBit>
void visit_corrections(const TetMesh& dt, const CarvingPrediction& p, CarvingContexts contexts,
                       std::vector<uint8_t>& kept, CodeBit&& code_bit) {
  if (contexts == CarvingContexts::kAlphaNeighbours) {
    std::array<AdaptiveBit, kAlphaNeighbourContexts> models;
    for (uint32_t c : p.order) kept[c] ^= static_cast<uint8_t>(code_bit(models[p.context[c]], c));
    return;
  }
  // context(c) needs only what changed around c since alpha's prediction:
  // the neighbours decoded as wrong. p.context holds each cell's context
  // from alpha's verdicts alone (bucket and kept neighbours); a cell decoded
  // as wrong tells each neighbour (those decoded already do not look again),
  // so the pass costs a neighbour walk per wrong cell only.
  // (kExactMargin: each of these split by the cell's margin bucket;
  // kExactMarginShape: by its margin and shape buckets; kExactMarginShapeFlip:
  // and its flip bucket.)
  const int splits = contexts == CarvingContexts::kExactMargin        ? kMarginBuckets
                     : contexts == CarvingContexts::kExactMarginShape ? kMarginBuckets * kShapeBuckets
                     : contexts == CarvingContexts::kExactMarginShapeFlip
                         ? kMarginBuckets * kShapeBuckets * kFlipBuckets
                         : 1;
  std::vector<AdaptiveBit> models(static_cast<size_t>(kDecodedNeighbourContexts * splits));
  std::vector<int8_t> kept_change(dt.cells.size(), 0);  // kept neighbours gained (lost)
  std::vector<uint8_t> wrong(dt.cells.size(), 0);       // neighbours decoded as wrong
  for (uint32_t c : p.order) {
    int context = (p.context[c] + kept_change[c]) * 3 + std::min<int>(wrong[c], 2);
    if (splits > 1) context = context * splits + p.margin[c];
    if (!code_bit(models[static_cast<size_t>(context)], c)) continue;
    kept[c] ^= 1;
    for (int32_t n : dt.neighbors[c]) {
      if (n < 0) continue;
      const auto k = static_cast<size_t>(n);
      kept_change[k] = static_cast<int8_t>(kept_change[k] + (kept[c] ? 1 : -1));
      ++wrong[k];
    }
  }
}

// The cells of each chunk, in `order` (chunk_cells() with a layer's ranked
// order).
ChunkCells group_by_chunk(std::span<const uint32_t> order, std::span<const uint32_t> chunk_of_cell,
                          size_t chunk_count);

// One chunk's traversal (6.0's contexts): as visit_corrections, but a wrong
// verdict tells only the neighbours of the same chunk. Chunks touch
// disjoint cells of `kept`, `kept_change` and `wrong`: they may run at once.
template <class CodeBit>
void visit_chunk(const TetMesh& dt, const CarvingPrediction& p, std::span<const uint32_t> cells,
                 std::span<const uint32_t> chunk_of_cell, std::vector<uint8_t>& kept,
                 std::vector<int8_t>& kept_change, std::vector<uint8_t>& wrong, CodeBit&& code_bit) {
  std::array<AdaptiveBit, kDecodedNeighbourContexts> models;
  for (uint32_t c : cells) {
    const int context = (p.context[c] + kept_change[c]) * 3 + std::min<int>(wrong[c], 2);
    if (!code_bit(models[static_cast<size_t>(context)], c)) continue;
    kept[c] ^= 1;
    for (int32_t n : dt.neighbors[c]) {
      if (n < 0 || chunk_of_cell[static_cast<size_t>(n)] != chunk_of_cell[c]) continue;
      const auto k = static_cast<size_t>(n);
      kept_change[k] = static_cast<int8_t>(kept_change[k] + (kept[c] ? 1 : -1));
      ++wrong[k];
    }
  }
}

// A bricked layer's coding order: the cells by their vertices' ranks
// (each cell's ascending, cells ascending), as canonical_cell_order orders
// them by vertex number.
std::vector<uint32_t> ranked_order(const TetMesh& dt, std::span<const uint32_t> vertex_rank);

}  // namespace dtm
