// A bricked layer's index (format 8.0, spec/FORMAT.md §3.5), below the layer
// checksum: the parser refuses it, or gives chunks in ascending brick order
// whose points and bytes add up to the layer's, and writing them back gives
// the same bytes.
#include <cstdint>
#include <span>

#include "codec/bricks/brick_index_encoder.h"
#include "codec/bricks/bricks.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // 6 parameter bytes: qbits (and in its high part whether the layer is
  // level 0's and the stream's flag faces), depth (and in its high part the
  // stream's flags carving_corrections, values, regions and cell_data), the
  // layer's points and chunk bytes (u16 each).
  if (size < 6) return 0;
  const int qbits = 1 + data[0] % 24;
  const int depth = data[1] % 18;  // 17: beyond the format's 16
  const uint16_t flags = static_cast<uint16_t>(
      ((data[1] / 18) & 1 ? dtm::kFlagCarvingCorrections : 0) | ((data[1] / 36) & 1 ? dtm::kFlagValues : 0) |
      ((data[1] / 72) & 1 ? dtm::kFlagRegions : 0) | ((data[1] / 144) & 1 ? dtm::kFlagCellData : 0) |
      ((data[0] / 48) & 1 ? dtm::kFlagFaces : 0));
  const int level = data[0] / 24 % 2;  // level 0's index holds the cell value bytes
  const uint64_t new_vertices = data[2] | (data[3] << 8);
  const uint64_t chunk_bytes = data[4] | (data[5] << 8);
  const std::span<const uint8_t> index(data + 6, size - 6);
  std::vector<dtm::BrickChunk> chunks;
  if (!dtm::parse_brick_index(index, depth, qbits, new_vertices, chunk_bytes, flags, level, chunks).ok())
    return 0;
  FUZZ_CHECK(depth <= qbits && depth <= dtm::kMaxBrickDepth);
  uint64_t points = 0, bytes = 0;
  for (size_t i = 0; i < chunks.size(); ++i) {
    FUZZ_CHECK(i == 0 || chunks[i].brick > chunks[i - 1].brick);
    FUZZ_CHECK(chunks[i].brick < (uint64_t{1} << (3 * depth)));
    FUZZ_CHECK(chunks[i].offset == bytes && chunks[i].points_before == points);
    FUZZ_CHECK(chunks[i].size() > 0);
    FUZZ_CHECK(chunks[i].carving_bytes == 0 || (flags & dtm::kFlagCarvingCorrections));
    FUZZ_CHECK((chunks[i].value_bytes > 0) == ((flags & dtm::kFlagValues) && chunks[i].new_points > 0));
    FUZZ_CHECK(chunks[i].region_bytes == 0 || (flags & dtm::kFlagRegions));
    FUZZ_CHECK(chunks[i].face_bytes == 0 || (flags & dtm::kFlagFaces));
    FUZZ_CHECK(chunks[i].cell_value_bytes == 0 || ((flags & dtm::kFlagCellData) && level == 0));
    FUZZ_CHECK(chunks[i].cell_value_checksum == 0 || chunks[i].cell_value_bytes > 0);
    points += chunks[i].new_points;
    bytes += chunks[i].size();
  }
  FUZZ_CHECK(points == new_vertices && bytes == chunk_bytes);
  const std::vector<uint8_t> again = dtm::write_brick_index(chunks, dtm::index_fields(flags, level));
  FUZZ_CHECK(std::equal(again.begin(), again.end(), index.begin(), index.end()));
  return 0;
}
