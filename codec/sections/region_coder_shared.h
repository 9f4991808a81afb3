// What the region coder's encoder (region_encoder.cpp) and decoder
// (region_decoder.cpp) share: the traversal both sides make (spec/FORMAT.md
// §3.6). Both sides must visit the cells and choose the models identically;
// it is written here once.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "bitstream/range_coder.h"
#include "codec/sections/region_coder.h"

namespace dtm {

// The regions a cell's decoded face neighbours have: distinct, the most
// frequent first (ties: the lower region first); `neighbours` counts the
// decoded ones.
struct NeighbourRegions {
  int neighbours = 0;
  int count = 0;
  std::array<uint8_t, 4> regions{};
};
inline NeighbourRegions neighbour_regions(const TetMesh& dt, uint32_t c, std::span<const uint8_t> decoded) {
  NeighbourRegions out;
  std::array<int, 4> votes{};
  for (int32_t n : dt.neighbors[c]) {
    if (n < 0) continue;
    const uint8_t r = decoded[static_cast<size_t>(n)];
    if (r == 0) continue;
    ++out.neighbours;
    int i = 0;
    while (i < out.count && out.regions[static_cast<size_t>(i)] != r) ++i;
    if (i == out.count) out.regions[static_cast<size_t>(out.count++)] = r;
    ++votes[static_cast<size_t>(i)];
  }
  // At most four: an insertion sort by votes, then region.
  for (int i = 1; i < out.count; ++i)
    for (int j = i; j > 0; --j) {
      const auto a = static_cast<size_t>(j - 1), b = static_cast<size_t>(j);
      if (votes[b] > votes[a] || (votes[b] == votes[a] && out.regions[b] < out.regions[a])) {
        std::swap(votes[a], votes[b]);
        std::swap(out.regions[a], out.regions[b]);
      } else {
        break;
      }
    }
  return out;
}

struct RegionModels {
  // Whether the cell takes the first guess: by decoded neighbours (0-4)
  // and whether they disagree.
  std::array<AdaptiveBit, 10> same;
  // Whether it takes another neighbour's region (by how many others: 1-3),
  // and which (a bit per step down the list).
  std::array<AdaptiveBit, 3> among_others;
  std::array<AdaptiveBit, 3> which_other;
  // Otherwise the region index (0-254), 8 bits from the highest, a model
  // per node of the binary tree.
  std::array<AdaptiveBit, 256> tree;
};

// The traversal: the kept cells in `order`, each coded by
// `code(models, guess, others, cell)` which returns its region (the
// encoder's writes it, the decoder's reads it), or 0 when the stream is
// damaged (the walk stops). `decoded` (per cell, 0 until coded) receives them.
template <class Code>
bool visit_regions(const TetMesh& dt, std::span<const uint32_t> order, std::span<const uint8_t> kept,
                   std::vector<uint8_t>& decoded, Code&& code) {
  RegionModels models;
  decoded.assign(dt.cells.size(), 0);
  uint8_t previous = 1;  // a cell with no decoded neighbour: guess the last region coded
  for (uint32_t c : order) {
    if (!kept[c]) continue;
    const NeighbourRegions n = neighbour_regions(dt, c, decoded);
    const uint8_t r = code(models, n, previous, c);
    if (r == 0) return false;
    decoded[c] = previous = r;
  }
  return true;
}

inline size_t same_context(const NeighbourRegions& n) {
  return static_cast<size_t>(n.neighbours) * 2 + (n.count > 1 ? 1 : 0);
}

}  // namespace dtm
