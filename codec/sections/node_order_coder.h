// A second-order mesh's node numbering (format 21.0, spec/FORMAT.md §3.13;
// meshenc --exact --keep-order of a second-order mesh), encoder and decoder
// side by side.
//
// The vertex order section (§3.9) gives level 0's vertices the input's
// order; the edge nodes (§3.11) come in the order the decoder walks the
// edges. A mesher numbers the two kinds together (gmsh entity by entity,
// the corners and the edge nodes of each interleaved; Netgen the corners
// first), and a user whose other files name the input's node ids needs both
// back where the file had them. This section gives the input's nodes in
// turn: whether each is a vertex (the next one of the vertex order) or an
// edge node, and which edge node: a mesher makes an element's edge nodes
// together, so the next one is often on an edge of a cell around the last
// one's edge (its index among the unnamed nodes there), else its rank among
// every node not yet named. 7.7-10.3 bits an edge node on gmsh's and
// Netgen's numberings (a random one: log2(nodes) - 1.44;
// bench/results/NODE_ORDER.md).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/edge_node_coder.h"
#include "common/csr.h"
#include "common/status.h"

namespace dtm {

// What both sides need of level 0's edges: the present nodes' edges in
// the walk's order (node r is on edge edge_of[r]), each present edge's node
// (node_of; kNoNode for an edge without one), and per edge the kept cells
// that have it (indices into LevelEdges::cell_edges).
struct NodeOrderFrame {
  static constexpr uint32_t kNoNode = UINT32_MAX;
  std::vector<uint32_t> edge_of;
  std::vector<uint32_t> node_of;
  Csr cells_of_edge;
};
NodeOrderFrame node_order_frame(const LevelEdges& edges, std::span<const uint8_t> present);

// `numbering`: the input's nodes in its order, vertices.size() + nodes in
// all: an entry below `vertices` is a vertex (they come in ascending
// order: the vertex order section has numbered them), vertices + r the
// present node r. The encoder takes a valid numbering (its caller checks).
std::vector<uint8_t> encode_node_order(const LevelEdges& edges, const NodeOrderFrame& frame, size_t vertices,
                                       std::span<const uint32_t> numbering);
// kCorrupt unless the section names every vertex and node exactly once
// and ends where its bytes do.
Status decode_node_order(std::span<const uint8_t> section, const LevelEdges& edges,
                         const NodeOrderFrame& frame, size_t vertices, std::vector<uint32_t>& numbering);

}  // namespace dtm
