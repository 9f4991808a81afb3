// The region table and sections written (spec/FORMAT.md §2.2, §3.6): the
// encoder's side of region_coder.h.
#include <string>
#include <vector>

#include "codec/sections/label_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/stream/table_framing.h"
#include "common/byte_io.h"
#include "common/checksum.h"
#include "common/parallel_for.h"

namespace dtm {

Status check_region_table(std::span<const RegionLabel> regions) {
  if (regions.empty() || regions.size() > kMaxRegionCount)
    return invalid_input("the input has " + std::to_string(regions.size()) +
                         " regions; a stream holds 1 to " + std::to_string(kMaxRegionCount));
  for (size_t i = 0; i < regions.size(); ++i) {
    if (regions[i].name.size() > kMaxRegionNameBytes)
      return invalid_input("region " + std::to_string(regions[i].label) + "'s name has more than " +
                           std::to_string(kMaxRegionNameBytes) + " bytes");
    for (size_t j = 0; j < i; ++j)
      if (regions[j].label == regions[i].label)
        return invalid_input("two regions are labelled " + std::to_string(regions[i].label));
  }
  return Status::Ok();
}

std::vector<uint8_t> write_region_table(std::span<const RegionLabel> regions) {
  ByteWriter body;
  body.u8(static_cast<uint8_t>(regions.size()));
  for (const RegionLabel& r : regions) {
    body.u32(static_cast<uint32_t>(r.label));
    body.u8(static_cast<uint8_t>(r.name.size()));
    for (char ch : r.name) body.u8(static_cast<uint8_t>(ch));
  }
  return frame_table(body.data());
}

std::vector<uint8_t> encode_regions(const TetMesh& dt, std::span<const uint32_t> order,
                                    std::span<const uint8_t> region, size_t region_count) {
  if (region_count < 2) return {};
  RangeEncoder rc;
  std::vector<uint8_t> decoded;
  visit_labels(
      dt.cells.size(), order, region, [&](uint32_t c) { return dt.neighbors[c]; }, decoded,
      [&](LabelModels& m, const NeighbourLabels& n, uint8_t previous, uint32_t c) {
        encode_label(rc, m, n, previous, region[c]);
        return region[c];
      });
  return rc.finish();
}

std::vector<std::vector<uint8_t>> encode_region_chunks(const TetMesh& dt, const ChunkCells& chunks,
                                                       std::span<const uint32_t> chunk_of_cell,
                                                       std::span<const uint8_t> region, size_t region_count) {
  const size_t count = chunks.first.empty() ? 0 : chunks.first.size() - 1;
  std::vector<std::vector<uint8_t>> out(count);
  if (region_count < 2) return out;
  std::vector<uint8_t> decoded(dt.cells.size(), 0);
  parallel_for(
      count,
      [&](size_t i) {
        const std::span<const uint32_t> cells(chunks.cells.data() + chunks.first[i],
                                              chunks.first[i + 1] - chunks.first[i]);
        if (std::none_of(cells.begin(), cells.end(), [&](uint32_t c) { return region[c] != 0; })) return;
        RangeEncoder rc;
        visit_label_run(
            cells, region, [&](uint32_t c) { return same_chunk_neighbours(dt, chunk_of_cell, c); }, decoded,
            [&](LabelModels& m, const NeighbourLabels& n, uint8_t previous, uint32_t c) {
              encode_label(rc, m, n, previous, region[c]);
              return region[c];
            });
        out[i] = rc.finish();
      },
      2);
  return out;
}

}  // namespace dtm
