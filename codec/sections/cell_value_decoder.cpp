// The cell value section read (spec/FORMAT.md §3.8), and where a cell
// stands, which encoder and decoder share.
#include "codec/sections/cell_value_coder.h"

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

}  // namespace dtm
