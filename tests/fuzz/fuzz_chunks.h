// A bricked layer's chunks over a fixed tetrahedralization, as the section
// targets take them (regions and cell values, spec/FORMAT.md §3.5): three
// chunks, each cell's by its second vertex, the vertices ranked by their
// number; the section's first two bytes give the first two chunks'
// lengths, the rest is the third's.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "codec/sections/carving_coder.h"
#include "mesh/delaunay.h"

struct FuzzChunks {
  std::vector<uint32_t> chunk_of_cell;
  dtm::ChunkCells cells;
  std::vector<std::span<const uint8_t>> sections;
};

// False (nothing to decode) when `section` has fewer than 2 bytes.
inline bool fuzz_chunks(const dtm::TetMesh& dt, size_t points, std::span<const uint8_t> section,
                        FuzzChunks& out) {
  if (section.size() < 2) return false;
  out.chunk_of_cell.resize(dt.cells.size());
  for (size_t c = 0; c < dt.cells.size(); ++c) out.chunk_of_cell[c] = dt.cells[c][1] % 3;
  std::vector<uint32_t> rank(points);
  std::iota(rank.begin(), rank.end(), 0u);
  out.cells = dtm::chunk_cells(dt, out.chunk_of_cell, 3, rank);
  const size_t first = std::min<size_t>(section[0], section.size() - 2);
  const size_t second = std::min<size_t>(section[1], section.size() - 2 - first);
  const std::span<const uint8_t> bytes = section.subspan(2);
  out.sections = {bytes.first(first), bytes.subspan(first, second), bytes.subspan(first + second)};
  return true;
}
