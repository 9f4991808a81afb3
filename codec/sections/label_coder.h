// A label per node of a graph, each coded from the labels of its
// neighbours decoded before it (spec/FORMAT.md §3.6): the regions of a
// level's kept cells (their face neighbours, region_coder.h) and the tags of
// its surface faces (the faces sharing an edge, face_coder.h). Encoder and
// decoder share it: both must visit the nodes and choose the models alike.
//
// A label is 1..count (0: a node not coded, or not decoded yet). Its guess
// is the label most of its decoded neighbours have (ties: the lower), or,
// with none decoded, the label coded last; a bit says whether the guess is
// right, then whether it is another decoded neighbour's (and which), else
// the label's index in 8 bits.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "bitstream/range_coder.h"

namespace dtm {

// The labels of a node's decoded neighbours: distinct, the most frequent
// first (ties: the lower label first), the first four of them;
// `neighbours` counts the decoded neighbours, at most 4.
struct NeighbourLabels {
  int neighbours = 0;
  int count = 0;
  std::array<uint8_t, 4> labels{};
};

template <class Neighbours>
NeighbourLabels neighbour_labels(const Neighbours& neighbours, std::span<const uint8_t> decoded) {
  // A node has few neighbours (4 face neighbours; mostly 3 faces for a
  // surface face, more at a pinch): votes per label in a table of every
  // label, zero between calls (the labels seen are cleared at the end).
  thread_local std::array<uint32_t, 256> votes{};
  std::array<uint8_t, 256> seen;
  int distinct = 0, decoded_neighbours = 0;
  for (const auto n : neighbours) {
    if constexpr (std::is_signed_v<std::remove_cvref_t<decltype(n)>>)
      if (n < 0) continue;
    const uint8_t label = decoded[static_cast<size_t>(n)];
    if (label == 0) continue;
    ++decoded_neighbours;
    if (votes[label]++ == 0) seen[static_cast<size_t>(distinct++)] = label;
  }
  std::sort(seen.begin(), seen.begin() + distinct,
            [&](uint8_t a, uint8_t b) { return votes[a] != votes[b] ? votes[a] > votes[b] : a < b; });
  NeighbourLabels out;
  out.neighbours = std::min(decoded_neighbours, 4);
  out.count = std::min(distinct, 4);
  for (int i = 0; i < out.count; ++i) out.labels[static_cast<size_t>(i)] = seen[static_cast<size_t>(i)];
  for (int i = 0; i < distinct; ++i) votes[seen[static_cast<size_t>(i)]] = 0;
  return out;
}

struct LabelModels {
  // Whether the node takes the guess: by decoded neighbours (0-4) and
  // whether they disagree.
  std::array<AdaptiveBit, 10> same;
  // Whether it takes another neighbour's label (by how many others: 1-3),
  // and which (a bit per step down the list).
  std::array<AdaptiveBit, 3> among_others;
  std::array<AdaptiveBit, 3> which_other;
  // Otherwise the label's index (label - 1, 0-255), 8 bits from the
  // highest, a model per node of the binary tree.
  std::array<AdaptiveBit, 256> tree;
};

inline size_t same_context(const NeighbourLabels& n) {
  return static_cast<size_t>(n.neighbours) * 2 + (n.count > 1 ? 1 : 0);
}

inline void encode_label(RangeEncoder& rc, LabelModels& m, const NeighbourLabels& n, uint8_t previous,
                         uint8_t label) {
  const uint8_t guess = n.count ? n.labels[0] : previous;
  rc.encode(m.same[same_context(n)], label == guess);
  if (label == guess) return;
  const int others = n.count > 0 ? n.count - 1 : 0;
  int at = 0;
  while (at < others && n.labels[static_cast<size_t>(at) + 1] != label) ++at;
  if (others > 0) {
    rc.encode(m.among_others[static_cast<size_t>(others - 1)], at < others);
    if (at < others) {
      for (int k = 0; k + 1 < others; ++k) {
        rc.encode(m.which_other[static_cast<size_t>(k)], at == k);
        if (at == k) break;
      }
      return;
    }
  }
  const unsigned index = label - 1u;
  size_t node = 1;
  for (int b = 7; b >= 0; --b) {
    const bool bit = (index >> b) & 1u;
    rc.encode(m.tree[node], bit);
    node = node * 2 + (bit ? 1 : 0);
  }
}

// The label, or 0 when the stream names one above `count` (damaged).
inline uint8_t decode_label(RangeDecoder& rc, LabelModels& m, const NeighbourLabels& n, uint8_t previous,
                            size_t count) {
  const uint8_t guess = n.count ? n.labels[0] : previous;
  if (rc.decode(m.same[same_context(n)])) return guess;
  const int others = n.count > 0 ? n.count - 1 : 0;
  if (others > 0 && rc.decode(m.among_others[static_cast<size_t>(others - 1)])) {
    int k = 0;
    while (k + 1 < others && !rc.decode(m.which_other[static_cast<size_t>(k)])) ++k;
    return n.labels[static_cast<size_t>(k) + 1];
  }
  size_t node = 1;
  for (int b = 7; b >= 0; --b) node = node * 2 + (rc.decode(m.tree[node]) ? 1 : 0);
  const size_t index = node - 256;
  if (index >= count || rc.overran()) return 0;
  return static_cast<uint8_t>(index + 1);
}

// A cell's face neighbours in its own chunk of a bricked layer (others -1):
// what its region's context reads (region_coder.h).
template <class Mesh>
std::array<int32_t, 4> same_chunk_neighbours(const Mesh& dt, std::span<const uint32_t> chunk_of_cell,
                                             uint32_t c) {
  std::array<int32_t, 4> out = dt.neighbors[c];
  for (int32_t& n : out)
    if (n >= 0 && chunk_of_cell[static_cast<size_t>(n)] != chunk_of_cell[c]) n = -1;
  return out;
}

// One run of nodes with fresh models: the nodes of `order` that `coded`
// flags, each coded by `code(models, neighbour labels, previous label,
// node)`, which returns its label (the encoder's writes it, the decoder's
// reads it), or 0 when the stream is damaged (the walk stops, false).
// `neighbours_of(node)` gives the node's neighbours (negative: none).
// Writes only the run's entries of `decoded`, which must be 0 before; where
// `neighbours_of` gives only nodes of the run (a chunk of a bricked layer,
// region_coder.h), runs over disjoint nodes may go at once.
template <class NeighboursOf, class Code>
bool visit_label_run(std::span<const uint32_t> order, std::span<const uint8_t> coded,
                     const NeighboursOf& neighbours_of, std::span<uint8_t> decoded, Code&& code) {
  LabelModels models;
  uint8_t previous = 1;  // a node with no decoded neighbour: guess the last label coded
  for (uint32_t c : order) {
    if (!coded.empty() && !coded[c]) continue;
    const NeighbourLabels n = neighbour_labels(neighbours_of(c), std::span<const uint8_t>(decoded));
    const uint8_t label = code(models, n, previous, c);
    if (label == 0) return false;
    decoded[c] = previous = label;
  }
  return true;
}

// The traversal of a whole level: one run over all its nodes; `decoded`
// receives the labels (0 for nodes not coded).
template <class NeighboursOf, class Code>
bool visit_labels(size_t nodes, std::span<const uint32_t> order, std::span<const uint8_t> coded,
                  const NeighboursOf& neighbours_of, std::vector<uint8_t>& decoded, Code&& code) {
  decoded.assign(nodes, 0);
  return visit_label_run(order, coded, neighbours_of, std::span<uint8_t>(decoded), code);
}

}  // namespace dtm
