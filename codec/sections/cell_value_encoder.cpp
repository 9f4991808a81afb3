// Level 0's cell values in a bricked layer's chunks, written (spec/FORMAT.md
// §3.5, 16.0): the encoder's side of cell_value_coder.h.
#include <algorithm>

#include "codec/sections/cell_value_coder.h"
#include "common/parallel_for.h"

namespace dtm {

std::vector<std::vector<uint8_t>> encode_cell_value_chunks(
    const FieldSectionEncoder& values, const TetMesh& dt, std::span<const GridPoint> points,
    const ChunkCells& chunks, std::span<const uint8_t> kept,
    const std::function<uint32_t(uint32_t cell)>& source_of, std::vector<uint64_t>& field_bytes) {
  const size_t count = chunks.first.empty() ? 0 : chunks.first.size() - 1;
  std::vector<std::vector<uint8_t>> out(count);
  std::vector<std::vector<uint64_t>> shares(count);
  parallel_for(
      count,
      [&](size_t i) {
        std::vector<std::array<uint32_t, 4>> cells;
        std::vector<uint32_t> sources;
        for (size_t k = chunks.first[i]; k < chunks.first[i + 1]; ++k) {
          const uint32_t c = chunks.cells[k];
          if (!kept[c]) continue;
          cells.push_back(dt.cells[c]);
          sources.push_back(source_of(c));
        }
        if (cells.empty()) return;
        out[i] = values.encode_chunk({}, {}, sources, cell_positions(points, cells), shares[i]);
      },
      2);
  field_bytes.resize(values.descriptions().size(), 0);
  for (const auto& s : shares)
    for (size_t f = 0; f < s.size(); ++f) field_bytes[f] += s[f];
  return out;
}

}  // namespace dtm
