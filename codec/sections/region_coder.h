// Regions (materials) of a stream's cells (spec/FORMAT.md §2.2, §3.6),
// encoder and decoder side by side. The region table, after the header's
// field table, names each region once: the label the input gave it (a gmsh
// physical volume, a Medit ref, a TetGen region attribute, a VTK cell
// array's value) and its name, if any. Each layer's region section then
// gives every kept cell of its level its region, in the carving's canonical
// order, predicted from the face neighbours decoded before it: a cell's
// region is almost always a neighbour's, so a level costs little more than
// its interfaces. A cell's region is the one whose input tetrahedra hold its
// centroid (core/region_solid.h): regions generalise the carving, whose
// "inside" they split. Each level's section is coded alone (fresh models).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "codec/sections/carving_coder.h"
#include "common/status.h"
#include "common/utf8.h"
#include "mesh/delaunay.h"

namespace dtm {

struct RegionLabel {
  int32_t label = 0;  // the input's own tag for the region
  std::string name;   // its name ($PhysicalNames), may be empty; at most 64 bytes
};
inline constexpr size_t kMaxRegionCount = 255;  // a cell's region is a byte, 0 = not kept
inline constexpr size_t kMaxRegionNameBytes = 64;

// A name as a table holds it: its first kMaxRegionNameBytes bytes, a UTF-8
// character not cut in two.
inline std::string held_label_name(std::string name) {
  return utf8_prefix(std::move(name), kMaxRegionNameBytes);
}

// The table: 1 to kMaxRegionCount regions, labels distinct.
Status check_region_table(std::span<const RegionLabel> regions);
std::vector<uint8_t> write_region_table(std::span<const RegionLabel> regions);
// kNeedMoreInput until the whole table is in `bytes`; kCorrupt if it is
// not a valid table. `consumed`: its size.
Status parse_region_table(std::span<const uint8_t> bytes, std::vector<RegionLabel>& regions,
                          size_t& consumed);

// The section for the regions `region` (per cell of `dt`: 0 not kept, else
// 1 + the region's index) of the kept cells, visited in `order` (the
// canonical order, mesh/topology.h). Empty with one region.
std::vector<uint8_t> encode_regions(const TetMesh& dt, std::span<const uint32_t> order,
                                    std::span<const uint8_t> region, size_t region_count);
// `region` holds the kept cells (non-zero) and leaves with their regions.
// kCorrupt if a region index is out of the table, or the section does not
// end where its bytes do.
Status decode_regions(std::span<const uint8_t> section, const TetMesh& dt, std::span<const uint32_t> order,
                      size_t region_count, std::vector<uint8_t>& region);

// Bricked layers (15.0, spec/FORMAT.md §3.5): a section per chunk, over the
// kept cells its brick owns, in its carving section's order (`chunks`,
// chunk_cells()), each cell's decoded neighbours those of the same chunk:
// chunks code alone, and a region reader decodes those it reads. One
// section for each chunk; with one region every one empty, else one with
// bytes for each chunk that owns a kept cell.
std::vector<std::vector<uint8_t>> encode_region_chunks(const TetMesh& dt, const ChunkCells& chunks,
                                                       std::span<const uint32_t> chunk_of_cell,
                                                       std::span<const uint8_t> region, size_t region_count);
// `region` holds the kept cells (non-zero) and leaves with their regions, on
// every core. kCorrupt, naming the chunk (its index), if a section is not
// one region_count allows, does not end where its bytes do, or a kept
// cell's brick has no chunk (`chunk_of_cell`: kNoCarvingChunk).
Status decode_region_chunks(std::span<const std::span<const uint8_t>> sections, const TetMesh& dt,
                            const ChunkCells& chunks, std::span<const uint32_t> chunk_of_cell,
                            size_t region_count, std::vector<uint8_t>& region);

}  // namespace dtm
