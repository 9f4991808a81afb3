// The cell value section read (spec/FORMAT.md §3.8), and where a cell
// stands, which encoder and decoder share.
#include <algorithm>
#include <string>

#include "codec/sections/cell_value_coder.h"
#include "common/parallel_for.h"

namespace dtm {

std::vector<GridPoint> cell_positions(std::span<const GridPoint> points,
                                      std::span<const std::array<uint32_t, 4>> cells) {
  std::vector<GridPoint> out;
  out.reserve(cells.size());
  for (const auto& c : cells) {
    GridPoint s{0, 0, 0};
    for (uint32_t v : c) s.x += points[v].x, s.y += points[v].y, s.z += points[v].z;
    out.push_back(s);
  }
  return out;
}

Status decode_cell_values(std::span<const FieldDescription> fields, std::span<const uint8_t> section,
                          std::span<const GridPoint> positions, std::vector<FieldValues>& out) {
  FieldSectionDecoder decoder(std::vector<FieldDescription>(fields.begin(), fields.end()));
  return decoder.decode_layer(section, positions, out);
}

std::vector<uint32_t> kept_cell_slots(std::span<const uint8_t> kept, uint64_t& count) {
  std::vector<uint32_t> slot(kept.size(), 0);
  count = 0;
  for (size_t c = 0; c < kept.size(); ++c)
    if (kept[c]) slot[c] = static_cast<uint32_t>(count++);
  return slot;
}

Status decode_cell_value_chunks(std::span<const FieldDescription> fields,
                                std::span<const std::span<const uint8_t>> sections, const TetMesh& dt,
                                std::span<const GridPoint> points, const ChunkCells& chunks,
                                std::span<const uint32_t> chunk_of_cell, std::span<const uint8_t> kept,
                                std::vector<FieldValues>& out) {
  const size_t count = sections.size();
  if (chunks.first.size() != count + 1 || kept.size() != dt.cells.size())
    return {StatusCode::kInternal, "decode_cell_value_chunks: the chunks' cells do not match the sections"};
  // Every kept cell is some chunk's (its brick's).
  for (size_t c = 0; c < kept.size(); ++c)
    if (kept[c] && chunk_of_cell[c] == kNoCarvingChunk)
      return {StatusCode::kCorrupt, "a kept cell whose brick has no chunk for its values"};
  uint64_t kept_count = 0;
  const std::vector<uint32_t> slot = kept_cell_slots(kept, kept_count);
  out.clear();
  for (const FieldDescription& f : fields)
    out.push_back({f, std::vector<uint64_t>(kept_count * static_cast<size_t>(f.components), 0)});
  std::vector<Status> status(count);
  parallel_for(
      count,
      [&](size_t i) {
        std::vector<uint32_t> ids;
        for (size_t k = chunks.first[i]; k < chunks.first[i + 1]; ++k)
          if (kept[chunks.cells[k]]) ids.push_back(chunks.cells[k]);
        const std::string where = "chunk " + std::to_string(i);
        if (ids.empty() != sections[i].empty()) {
          status[i] = {StatusCode::kCorrupt,
                       where + (ids.empty() ? ": a cell value section without kept cells"
                                            : ": kept cells without a cell value section")};
          return;
        }
        if (ids.empty()) return;
        std::vector<std::array<uint32_t, 4>> cells;
        cells.reserve(ids.size());
        for (uint32_t c : ids) cells.push_back(dt.cells[c]);
        std::vector<FieldValues> decoded;
        status[i] = decode_chunk_values(fields, sections[i], {}, {}, cell_positions(points, cells), decoded)
                        .with_context(where + "'s cell values");
        if (!status[i].ok()) return;
        // (Each cell is one chunk's: the chunks write disjoint places.)
        for (size_t f = 0; f < fields.size(); ++f) {
          const auto n = static_cast<size_t>(fields[f].components);
          for (size_t k = 0; k < ids.size(); ++k)
            std::copy_n(decoded[f].bits.begin() + static_cast<std::ptrdiff_t>(k * n), n,
                        out[f].bits.begin() + static_cast<std::ptrdiff_t>(size_t{slot[ids[k]]} * n));
        }
      },
      2);
  for (const Status& s : status) DTM_RETURN_IF_ERROR(s);
  return Status::Ok();
}

}  // namespace dtm
