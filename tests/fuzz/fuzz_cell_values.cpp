// The cell field table and level 0's cell value section (spec/FORMAT.md
// §2.4, §3.8) on arbitrary bytes, below the checksums that keep the stream
// targets from reaching them damaged: never a crash, never an allocation
// the bytes do not justify; a table that parses writes back to the same
// bytes, and a section that decodes gives every cell its values, which the
// encoder codes again into a section that decodes to the same values.
//
// Input: byte 0: which point set (fuzz_point_sets.h, by bit 0), which of
// its Delaunay cells are kept (all, by bit 1, else every cell whose first
// vertex is even), and by bit 2 whether the section is a bricked level 0's
// (16.0, spec/FORMAT.md §3.5: three chunks, each cell's by its second
// vertex; the section's first two bytes give the first two chunks'
// lengths, the rest the third's); bytes 1-2: the table's body length n
// (little-endian); then n bytes of body (the target adds the length word
// and the checksum), then the section.
#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "codec/sections/cell_value_coder.h"
#include "fuzz_check.h"
#include "fuzz_chunks.h"
#include "fuzz_point_sets.h"
#include "fuzz_tables.h"
#include "mesh/delaunay.h"
#include "mesh/topology.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const bool cloud = data[0] & 1;
  static const dtm::TetMesh block_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(false)).value();
  static const dtm::TetMesh cloud_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(true)).value();
  const dtm::TetMesh& dt = cloud ? cloud_dt : block_dt;
  const FuzzTable framed = fuzz_table(data, size);
  const std::vector<uint8_t>& table = framed.table;
  std::vector<dtm::FieldDescription> fields;
  size_t consumed = 0;
  const dtm::Status parsed = dtm::parse_field_table(table, fields, consumed);
  if (!parsed.ok()) {
    FUZZ_CHECK(parsed.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(consumed == table.size());
  FUZZ_CHECK(dtm::write_field_table(fields) == table);

  const std::span<const uint8_t> section = framed.after;
  const std::span<const dtm::GridPoint> points = fuzz_point_set(cloud);
  if (data[0] & 4) {  // a bricked level 0's chunks
    std::vector<uint8_t> kept(dt.cells.size());
    for (size_t c = 0; c < kept.size(); ++c) kept[c] = (data[0] & 2) || dt.cells[c][0] % 2 == 0;
    FuzzChunks chunked;
    if (!fuzz_chunks(dt, points.size(), section, chunked)) return 0;
    const dtm::ChunkCells& chunks = chunked.cells;
    const std::vector<uint32_t>& chunk_of_cell = chunked.chunk_of_cell;
    std::vector<dtm::FieldValues> values;
    const dtm::Status s = dtm::decode_cell_value_chunks(fields, chunked.sections, dt, points, chunks,
                                                        chunk_of_cell, kept, values);
    if (!s.ok()) {
      FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
      return 0;
    }
    // The kept cells' values, in their index order.
    std::vector<uint32_t> slot(kept.size(), 0);
    uint32_t kept_count = 0;
    for (size_t c = 0; c < kept.size(); ++c)
      if (kept[c]) slot[c] = kept_count++;
    FUZZ_CHECK(values.size() == fields.size());
    for (size_t f = 0; f < fields.size(); ++f)
      FUZZ_CHECK(values[f].bits.size() == size_t{kept_count} * fields[f].components);
    if (std::any_of(fields.begin(), fields.end(), [](const auto& f) { return f.lossy; })) return 0;
    // Coded again chunk by chunk (each cell its own source), the same values.
    auto again = dtm::FieldSectionEncoder::make(values);
    FUZZ_CHECK(again.ok());
    std::vector<uint64_t> field_bytes;
    const auto recoded = dtm::encode_cell_value_chunks(
        *again, dt, points, chunks, kept, [&](uint32_t c) { return slot[c]; }, field_bytes);
    const std::vector<std::span<const uint8_t>> recoded_parts(recoded.begin(), recoded.end());
    std::vector<dtm::FieldValues> back;
    FUZZ_CHECK(dtm::decode_cell_value_chunks(again->descriptions(), recoded_parts, dt, points, chunks,
                                             chunk_of_cell, kept, back)
                   .ok());
    for (size_t f = 0; f < fields.size(); ++f) FUZZ_CHECK(back[f].bits == values[f].bits);
    return 0;
  }

  // The kept cells in canonical order, where the decoder puts them.
  std::vector<std::array<uint32_t, 4>> cells;
  for (uint32_t c : dtm::canonical_cell_order(dt.cells))
    if ((data[0] & 2) || dt.cells[c][0] % 2 == 0) cells.push_back(dt.cells[c]);
  const std::vector<dtm::GridPoint> at = dtm::cell_positions(points, cells);
  std::vector<dtm::FieldValues> values;
  const dtm::Status s = dtm::decode_cell_values(fields, section, at, values);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(values.size() == fields.size());
  for (size_t f = 0; f < fields.size(); ++f)
    FUZZ_CHECK(values[f].bits.size() == cells.size() * fields[f].components);
  // Lossless values code again to values that decode the same (a lossy
  // table's scales are the encoder's own, not re-derived here).
  if (std::any_of(fields.begin(), fields.end(), [](const auto& f) { return f.lossy; })) return 0;
  auto again = dtm::FieldSectionEncoder::make(values);
  FUZZ_CHECK(again.ok());
  std::vector<uint32_t> ids(cells.size());
  std::iota(ids.begin(), ids.end(), 0u);
  std::vector<uint64_t> bytes;
  const std::vector<uint8_t> recoded = again->encode_layer(ids, at, bytes);
  std::vector<dtm::FieldValues> back;
  FUZZ_CHECK(dtm::decode_cell_values(again->descriptions(), recoded, at, back).ok());
  for (size_t f = 0; f < fields.size(); ++f) FUZZ_CHECK(back[f].bits == values[f].bits);
  return 0;
}
