// The carving corrections written (spec/FORMAT.md §3.2, §3.5): the encoder's
// side of carving_coder.h.
#include <vector>

#include "codec/sections/carving_coder.h"
#include "codec/sections/carving_coder_shared.h"
#include "common/parallel_for.h"

namespace dtm {

std::vector<std::vector<uint8_t>> encode_carving_chunks(const TetMesh& dt, std::span<const GridPoint> points,
                                                        double alpha, std::span<const uint8_t> kept,
                                                        std::span<const uint32_t> chunk_of_cell,
                                                        const ChunkCells& cells) {
  const CarvingPrediction p =
      predict_carving(dt, points, alpha, CarvingContexts::kDecodedNeighbours, chunk_of_cell);
  const ChunkCells& g = cells;
  const size_t chunk_count = g.first.empty() ? 0 : g.first.size() - 1;
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

}  // namespace dtm
