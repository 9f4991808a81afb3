// The carving corrections read (spec/FORMAT.md §3.2, §3.5): the decoder's
// side of carving_coder.h.
#include <string>
#include <vector>

#include "codec/sections/carving_coder.h"
#include "codec/sections/carving_coder_shared.h"
#include "common/parallel_for.h"

namespace dtm {

Status decode_carving_chunks(std::span<const std::span<const uint8_t>> sections, const TetMesh& dt,
                             std::span<const GridPoint> points, double alpha,
                             std::span<const uint32_t> chunk_of_cell, std::span<const uint32_t> vertex_rank,
                             std::vector<uint8_t>& kept, std::vector<uint32_t>* order, ChunkCells* cells) {
  CarvingPrediction p =
      predict_carving(dt, points, alpha, CarvingContexts::kDecodedNeighbours, chunk_of_cell);
  ChunkCells g = chunk_cells(dt, chunk_of_cell, sections.size(), vertex_rank);
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
  if (cells) *cells = std::move(g);
  return Status::Ok();
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
