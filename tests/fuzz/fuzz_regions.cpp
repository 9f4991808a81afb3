// The region table and the region section (spec/FORMAT.md §2.2, §3.6) on
// arbitrary bytes, below the checksums that keep the stream targets from
// reaching them damaged: never a crash; a table that parses writes back to
// the same bytes; a section that decodes gives every kept cell a region of
// the table, and those regions re-encode to the same section.
//
// Input: byte 0: which point set (fuzz_point_sets.h, by bit 0), which cells
// are kept (all, by bit 1, else every cell whose first vertex is even), the
// region count (2 + bits 2-6), and by bit 7 whether the section is a
// bricked layer's (15.0, spec/FORMAT.md §3.5: three chunks, each cell's by
// its second vertex; the section's first two bytes give the first two
// chunks' lengths, the rest the third's); bytes 1-2: the table's body
// length n (little-endian); then n bytes of body (the target adds the
// length word and the checksum), then the section.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/region_coder.h"
#include "fuzz_check.h"
#include "fuzz_chunks.h"
#include "fuzz_point_sets.h"
#include "fuzz_tables.h"
#include "mesh/delaunay.h"
#include "mesh/topology.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  static const dtm::TetMesh block_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(false)).value();
  static const dtm::TetMesh cloud_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(true)).value();
  const dtm::TetMesh& dt = (data[0] & 1) ? cloud_dt : block_dt;
  const size_t regions = 2 + ((data[0] >> 2) & 31);
  const bool chunked = data[0] & 128;
  const FuzzTable framed = fuzz_table(data, size);
  const std::vector<uint8_t>& table = framed.table;
  std::vector<dtm::RegionLabel> labels;
  size_t consumed = 0;
  const dtm::Status parsed = dtm::parse_region_table(table, labels, consumed);
  if (parsed.ok()) {
    FUZZ_CHECK(consumed == table.size());
    FUZZ_CHECK(dtm::check_region_table(labels).ok());
    FUZZ_CHECK(dtm::write_region_table(labels) == table);
  } else {
    FUZZ_CHECK(parsed.code() == dtm::StatusCode::kCorrupt);
  }

  const std::span<const uint8_t> section = framed.after;
  static const std::vector<uint32_t> block_order = dtm::canonical_cell_order(block_dt.cells);
  static const std::vector<uint32_t> cloud_order = dtm::canonical_cell_order(cloud_dt.cells);
  const std::vector<uint32_t>& order = (data[0] & 1) ? cloud_order : block_order;
  std::vector<uint8_t> kept(dt.cells.size());
  for (size_t c = 0; c < kept.size(); ++c) kept[c] = (data[0] & 2) || dt.cells[c][0] % 2 == 0;
  std::vector<uint8_t> region = kept;
  if (chunked) {
    FuzzChunks chunked;
    if (!fuzz_chunks(dt, fuzz_point_set(data[0] & 1).size(), section, chunked)) return 0;
    const dtm::ChunkCells& chunks = chunked.cells;
    const std::vector<uint32_t>& chunk_of_cell = chunked.chunk_of_cell;
    const std::span<const std::span<const uint8_t>> parts = chunked.sections;
    const dtm::Status s = dtm::decode_region_chunks(parts, dt, chunks, chunk_of_cell, regions, region);
    if (!s.ok()) {
      FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
      return 0;
    }
    for (size_t c = 0; c < region.size(); ++c)
      FUZZ_CHECK((region[c] != 0) == (kept[c] != 0) && region[c] <= regions);
    const auto again = dtm::encode_region_chunks(dt, chunks, chunk_of_cell, region, regions);
    for (size_t k = 0; k < 3; ++k)
      FUZZ_CHECK(again[k] == std::vector<uint8_t>(parts[k].begin(), parts[k].end()));
    return 0;
  }
  const dtm::Status s = dtm::decode_regions(section, dt, order, regions, region);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(region.size() == dt.cells.size());
  for (size_t c = 0; c < region.size(); ++c)
    FUZZ_CHECK((region[c] != 0) == (kept[c] != 0) && region[c] <= regions);
  FUZZ_CHECK(dtm::encode_regions(dt, order, region, regions) ==
             std::vector<uint8_t>(section.begin(), section.end()));
  return 0;
}
