// The region table and sections read (spec/FORMAT.md §2.2, §3.6): the
// decoder's side of region_coder.h.
#include <string>
#include <vector>

#include "codec/sections/label_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/stream/table_framing.h"
#include "common/byte_io.h"
#include "common/checksum.h"
#include "common/parallel_for.h"

namespace dtm {
namespace {

Status table_corrupt(const std::string& what) { return {StatusCode::kCorrupt, "region table: " + what}; }

// The table's body: a count, then per region its label and name.
constexpr uint32_t kMaxTableBytes = 1 + kMaxRegionCount * (4 + 1 + kMaxRegionNameBytes);

}  // namespace

Status parse_region_table(std::span<const uint8_t> bytes, std::vector<RegionLabel>& regions,
                          size_t& consumed) {
  std::span<const uint8_t> body;
  size_t whole = 0;
  DTM_RETURN_IF_ERROR(unframe_table(bytes, kMaxTableBytes, "region table", body, whole));
  ByteReader r(body);
  uint8_t count = 0;
  r.u8(count);
  if (count == 0) return table_corrupt("no region");
  regions.clear();
  for (int i = 0; i < count; ++i) {
    RegionLabel region;
    uint32_t label = 0;
    uint8_t name_length = 0;
    if (!r.u32(label) || !r.u8(name_length)) return table_corrupt("ends inside a region");
    if (name_length > kMaxRegionNameBytes) return table_corrupt("a name is longer than 64 bytes");
    region.label = static_cast<int32_t>(label);
    for (int k = 0; k < name_length; ++k) {
      uint8_t ch = 0;
      if (!r.u8(ch)) return table_corrupt("ends inside a name");
      region.name.push_back(static_cast<char>(ch));
    }
    for (const RegionLabel& other : regions)
      if (other.label == region.label) return table_corrupt("two regions labelled " + std::to_string(label));
    regions.push_back(std::move(region));
  }
  if (r.remaining() != 0) return table_corrupt("bytes left over after the last region");
  consumed = whole;
  return Status::Ok();
}

Status decode_regions(std::span<const uint8_t> section, const TetMesh& dt, std::span<const uint32_t> order,
                      size_t region_count, std::vector<uint8_t>& region) {
  if (region_count < 2) {
    if (!section.empty()) return {StatusCode::kCorrupt, "a region section in a stream of one region"};
    for (uint8_t& r : region) r = r ? 1 : 0;
    return Status::Ok();
  }
  RangeDecoder rc(section);
  std::vector<uint8_t> decoded;
  const bool whole = visit_labels(
      dt.cells.size(), order, region, [&](uint32_t c) { return dt.neighbors[c]; }, decoded,
      [&](LabelModels& m, const NeighbourLabels& n, uint8_t previous, uint32_t) {
        return decode_label(rc, m, n, previous, region_count);
      });
  if (!whole) return {StatusCode::kCorrupt, "a cell's region is not in the region table"};
  if (!rc.finished_cleanly())
    return {StatusCode::kCorrupt,
            rc.overran() ? "the region section ends early" : "bytes after the region section"};
  region = std::move(decoded);
  return Status::Ok();
}

Status decode_region_chunks(std::span<const std::span<const uint8_t>> sections, const TetMesh& dt,
                            const ChunkCells& chunks, std::span<const uint32_t> chunk_of_cell,
                            size_t region_count, std::vector<uint8_t>& region) {
  const size_t count = sections.size();
  if (chunks.first.size() != count + 1)
    return {StatusCode::kInternal, "decode_region_chunks: the chunks' cells do not match the sections"};
  if (region_count < 2) {
    for (size_t i = 0; i < count; ++i)
      if (!sections[i].empty())
        return {StatusCode::kCorrupt,
                "chunk " + std::to_string(i) + ": a region section in a stream of one region"};
    for (uint8_t& r : region) r = r ? 1 : 0;
    return Status::Ok();
  }
  // Every kept cell is some chunk's (its brick's).
  for (size_t c = 0; c < region.size(); ++c)
    if (region[c] && chunk_of_cell[c] == kNoCarvingChunk)
      return {StatusCode::kCorrupt, "a kept cell whose brick has no chunk for its region"};
  std::vector<uint8_t> decoded(dt.cells.size(), 0);
  // Per chunk: 0 fine, 1 a region out of the table, 2 not ending where its
  // bytes do, 3 kept cells without a section, 4 a section without them.
  std::vector<uint8_t> damage(count, 0);
  parallel_for(
      count,
      [&](size_t i) {
        const std::span<const uint32_t> cells(chunks.cells.data() + chunks.first[i],
                                              chunks.first[i + 1] - chunks.first[i]);
        const bool any = std::any_of(cells.begin(), cells.end(), [&](uint32_t c) { return region[c] != 0; });
        if (any != !sections[i].empty()) {
          damage[i] = any ? 3 : 4;
          return;
        }
        if (!any) return;
        RangeDecoder rc(sections[i]);
        const bool whole = visit_label_run(
            cells, region, [&](uint32_t c) { return same_chunk_neighbours(dt, chunk_of_cell, c); }, decoded,
            [&](LabelModels& m, const NeighbourLabels& n, uint8_t previous, uint32_t) {
              return decode_label(rc, m, n, previous, region_count);
            });
        damage[i] = !whole ? 1 : !rc.finished_cleanly() ? 2 : 0;
      },
      2);
  static constexpr const char* kWhat[] = {
      "", "a cell's region is not in the region table", "its region section does not end where its bytes do",
      "kept cells without a region section", "a region section without kept cells"};
  for (size_t i = 0; i < count; ++i)
    if (damage[i]) return {StatusCode::kCorrupt, "chunk " + std::to_string(i) + ": " + kWhat[damage[i]]};
  region = std::move(decoded);
  return Status::Ok();
}

}  // namespace dtm
