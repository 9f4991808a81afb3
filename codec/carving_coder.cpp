#include "codec/carving_coder.h"

#include <algorithm>
#include <array>
#include <string>

#include "bitstream/range_coder.h"
#include "common/parallel_for.h"
#include "mesh/carving.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

// Circumradius over alpha, in quarter octaves from 2^-7/4 to 2^7/4: the
// bucket is how many of these the ratio exceeds (spec/FORMAT.md §3.2 lists
// them; products with alpha are exact IEEE operations, so both sides agree).
constexpr std::array<double, kCarvingRatioBuckets - 1> kRatioSteps = {
    0.29730177875068026, 0.3535533905932738, 0.42044820762685725, 0.5,
    0.5946035575013605,  0.7071067811865476, 0.8408964152537145,  1.0,
    1.189207115002721,   1.4142135623730951, 1.681792830507429,   2.0,
    2.378414230005442,   2.8284271247461903, 3.363585661014858};
static_assert(kRatioSteps[7] == 1.0, "bucket 8 and above: alpha removes the cell");

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
  std::array<AdaptiveBit, kDecodedNeighbourContexts> models;
  std::vector<int8_t> kept_change(dt.cells.size(), 0);  // kept neighbours gained (lost)
  std::vector<uint8_t> wrong(dt.cells.size(), 0);       // neighbours decoded as wrong
  for (uint32_t c : p.order) {
    const int context = (p.context[c] + kept_change[c]) * 3 + std::min<int>(wrong[c], 2);
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

// The cells of each chunk, in canonical order: chunk_cells[first[i] ..
// first[i + 1]) are chunk i's.
struct ChunkCells {
  std::vector<uint32_t> cells, first;
};
ChunkCells group_by_chunk(std::span<const uint32_t> order, std::span<const uint32_t> chunk_of_cell,
                          size_t chunk_count) {
  ChunkCells g;
  g.first.assign(chunk_count + 1, 0);
  for (uint32_t c : order)
    if (chunk_of_cell[c] != kNoCarvingChunk) ++g.first[chunk_of_cell[c] + 1];
  for (size_t i = 0; i < chunk_count; ++i) g.first[i + 1] += g.first[i];
  g.cells.resize(g.first[chunk_count]);
  std::vector<uint32_t> next(g.first.begin(), g.first.end() - 1);
  for (uint32_t c : order)
    if (chunk_of_cell[c] != kNoCarvingChunk) g.cells[next[chunk_of_cell[c]]++] = c;
  return g;
}

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
std::vector<uint32_t> ranked_order(const TetMesh& dt, std::span<const uint32_t> vertex_rank) {
  std::vector<std::array<uint32_t, 4>> ranked(dt.cells.size());
  for (size_t c = 0; c < ranked.size(); ++c)
    for (int i = 0; i < 4; ++i) ranked[c][i] = vertex_rank[dt.cells[c][i]];
  return canonical_cell_order(ranked);
}

}  // namespace

std::vector<std::vector<uint8_t>> encode_carving_chunks(const TetMesh& dt, std::span<const GridPoint> points,
                                                        double alpha, std::span<const uint8_t> kept,
                                                        std::span<const uint32_t> chunk_of_cell,
                                                        size_t chunk_count,
                                                        std::span<const uint32_t> vertex_rank) {
  const CarvingPrediction p =
      predict_carving(dt, points, alpha, CarvingContexts::kDecodedNeighbours, chunk_of_cell);
  const ChunkCells g = group_by_chunk(ranked_order(dt, vertex_rank), chunk_of_cell, chunk_count);
  std::vector<std::vector<uint8_t>> out(chunk_count);
  std::vector<uint8_t> verdicts = p.kept;
  std::vector<int8_t> kept_change(dt.cells.size(), 0);
  std::vector<uint8_t> wrong(dt.cells.size(), 0);
  parallel_for(
      chunk_count,
      [&](size_t i) {
        const std::span<const uint32_t> cells(g.cells.data() + g.first[i], g.first[i + 1] - g.first[i]);
        bool any = false;
        for (uint32_t c : cells) any = any || (kept[c] != 0) != (p.kept[c] != 0);
        if (!any) return;
        RangeEncoder rc;
        visit_chunk(dt, p, cells, chunk_of_cell, verdicts, kept_change, wrong,
                    [&](AdaptiveBit& model, uint32_t c) {
                      const bool is_wrong = (kept[c] != 0) != (p.kept[c] != 0);
                      rc.encode(model, is_wrong);
                      return is_wrong;
                    });
        out[i] = rc.finish();
      },
      2);
  return out;
}

Status decode_carving_chunks(std::span<const std::span<const uint8_t>> sections, const TetMesh& dt,
                             std::span<const GridPoint> points, double alpha,
                             std::span<const uint32_t> chunk_of_cell, std::span<const uint32_t> vertex_rank,
                             std::vector<uint8_t>& kept, std::vector<uint32_t>* order) {
  CarvingPrediction p =
      predict_carving(dt, points, alpha, CarvingContexts::kDecodedNeighbours, chunk_of_cell);
  const ChunkCells g = group_by_chunk(ranked_order(dt, vertex_rank), chunk_of_cell, sections.size());
  kept = p.kept;
  std::vector<int8_t> kept_change(dt.cells.size(), 0);
  std::vector<uint8_t> wrong(dt.cells.size(), 0);
  std::vector<uint8_t> damaged(sections.size(), 0);
  parallel_for(
      sections.size(),
      [&](size_t i) {
        if (sections[i].empty()) return;
        const std::span<const uint32_t> cells(g.cells.data() + g.first[i], g.first[i + 1] - g.first[i]);
        RangeDecoder rc(sections[i]);
        visit_chunk(dt, p, cells, chunk_of_cell, kept, kept_change, wrong,
                    [&](AdaptiveBit& model, uint32_t) { return rc.decode(model); });
        damaged[i] = !rc.finished_cleanly();
      },
      2);
  for (size_t i = 0; i < sections.size(); ++i)
    if (damaged[i])
      return {StatusCode::kCorrupt, "chunk " + std::to_string(i) +
                                        ": carving corrections do not end where "
                                        "their bytes do"};
  if (order) *order = std::move(p.order);
  return Status::Ok();
}

CarvingContexts carving_contexts(uint8_t format_major) {
  return format_major >= 6 ? CarvingContexts::kDecodedNeighbours : CarvingContexts::kAlphaNeighbours;
}

CarvingPrediction predict_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha,
                                  CarvingContexts contexts, std::span<const uint32_t> chunk_of_cell) {
  const size_t m = dt.cells.size();
  CarvingPrediction p;
  p.kept.resize(m);
  std::vector<uint8_t> bucket(m);
  // Each cell on its own: every core (the same bits whatever the split).
  constexpr size_t kBlock = 4096;
  const size_t blocks = (m + kBlock - 1) / kBlock;
  parallel_for(
      blocks,
      [&](size_t block) {
        for (size_t c = block * kBlock; c < std::min(m, block * kBlock + kBlock); ++c) {
          const double radius = carving_radius(points, dt.cells[c]);
          uint8_t b = 0;
          for (double step : kRatioSteps) b += radius > step * alpha;
          bucket[c] = b;
          p.kept[c] = radius <= alpha;
        }
      },
      2);
  // The context from alpha's verdicts: the whole of 4.0's, the start of 6.0's.
  const bool half_octaves = contexts == CarvingContexts::kDecodedNeighbours;
  p.context.resize(m);
  parallel_for(
      blocks,
      [&](size_t block) {
        for (size_t c = block * kBlock; c < std::min(m, block * kBlock + kBlock); ++c) {
          int kept_neighbors = 0;
          for (int32_t n : dt.neighbors[c])
            kept_neighbors +=
                n >= 0 && p.kept[static_cast<size_t>(n)] &&
                (chunk_of_cell.empty() || chunk_of_cell[static_cast<size_t>(n)] == chunk_of_cell[c]);
          p.context[c] =
              static_cast<uint8_t>((half_octaves ? bucket[c] / 2 : bucket[c]) * 5 + kept_neighbors);
        }
      },
      2);
  p.order = canonical_cell_order(dt.cells);  // the identity for an exported triangulation
  return p;
}

std::vector<uint8_t> encode_carving(const TetMesh& dt, std::span<const GridPoint> points, double alpha,
                                    std::span<const uint8_t> kept, CarvingContexts contexts) {
  const CarvingPrediction p = predict_carving(dt, points, alpha, contexts);
  bool any = false;
  for (size_t c = 0; c < kept.size() && !any; ++c) any = (kept[c] != 0) != (p.kept[c] != 0);
  if (!any) return {};
  RangeEncoder rc;
  std::vector<uint8_t> verdicts = p.kept;
  visit_corrections(dt, p, contexts, verdicts, [&](AdaptiveBit& model, uint32_t c) {
    const bool wrong = (kept[c] != 0) != (p.kept[c] != 0);
    rc.encode(model, wrong);
    return wrong;
  });
  return rc.finish();
}

Status decode_carving(std::span<const uint8_t> section, const TetMesh& dt, std::span<const GridPoint> points,
                      double alpha, CarvingContexts contexts, std::vector<uint8_t>& kept,
                      std::vector<uint32_t>* order) {
  CarvingPrediction p = predict_carving(dt, points, alpha, contexts);
  if (order) *order = p.order;
  if (section.empty()) {
    kept = std::move(p.kept);
    return Status::Ok();
  }
  kept = p.kept;
  RangeDecoder rc(section);
  visit_corrections(dt, p, contexts, kept, [&](AdaptiveBit& model, uint32_t) { return rc.decode(model); });
  if (!rc.finished_cleanly())
    return {StatusCode::kCorrupt,
            rc.overran() ? "carving corrections end early" : "bytes after the carving corrections"};
  return Status::Ok();
}

}  // namespace dtm
