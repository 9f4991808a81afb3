// The node order section read (spec/FORMAT.md §3.13), and the frame both
// sides build.
#include <algorithm>

#include "codec/sections/node_order_coder.h"
#include "codec/sections/node_order_coder_shared.h"

namespace dtm {

NodeOrderFrame node_order_frame(const LevelEdges& edges, std::span<const uint8_t> present) {
  NodeOrderFrame frame;
  frame.node_of.assign(edges.corners.size(), NodeOrderFrame::kNoNode);
  for (size_t e = 0; e < edges.corners.size() && e < present.size(); ++e)
    if (present[e]) {
      frame.node_of[e] = static_cast<uint32_t>(frame.edge_of.size());
      frame.edge_of.push_back(static_cast<uint32_t>(e));
    }
  frame.cells_of_edge = build_csr(edges.corners.size(), [&](auto&& emit) {
    for (size_t c = 0; c < edges.cell_edges.size(); ++c)
      for (uint32_t e : edges.cell_edges[c]) emit(e, static_cast<uint32_t>(c));
  });
  return frame;
}

Status decode_node_order(std::span<const uint8_t> section, const LevelEdges& edges,
                         const NodeOrderFrame& frame, size_t vertices, std::vector<uint32_t>& numbering) {
  const size_t nodes = frame.edge_of.size();
  numbering.clear();
  numbering.reserve(vertices + nodes);
  RangeDecoder rc(section);
  NodeOrderModels models;
  UnvisitedVertices unnamed(nodes);
  size_t vertices_left = vertices, nodes_left = nodes;
  bool last_was_node = false, before_was_node = false;
  uint32_t last_node = NodeOrderFrame::kNoNode;
  std::vector<uint32_t> near;
  for (size_t k = 0; k < vertices + nodes; ++k) {
    const bool is_node = vertices_left > 0 && nodes_left > 0
                             ? rc.decode(models.edge_for(last_was_node, before_was_node))
                             : nodes_left > 0;
    if (is_node) {
      bool named = false;
      uint32_t node = 0;
      if (last_node != NodeOrderFrame::kNoNode) {
        node_candidates(edges, frame, last_node, unnamed, near);
        if (!near.empty() && rc.decode(models.near_for(last_was_node, near.size()))) {
          uint64_t i = 0;
          if (!rc.decode_index(near.size(), i).ok()) return {StatusCode::kCorrupt, "node order: a bad index"};
          node = near[i];
          named = true;
        }
      }
      if (!named) {
        uint64_t r = 0;
        if (!rc.decode_index(unnamed.left(), r).ok()) return {StatusCode::kCorrupt, "node order: a bad rank"};
        node = unnamed.at(static_cast<uint32_t>(r));
      }
      unnamed.visit(node);
      last_node = node;
      --nodes_left;
      numbering.push_back(static_cast<uint32_t>(vertices + node));
    } else {
      numbering.push_back(static_cast<uint32_t>(vertices - vertices_left));
      --vertices_left;
    }
    if (rc.overran()) return {StatusCode::kCorrupt, "node order: the section ends early"};
    before_was_node = last_was_node;
    last_was_node = is_node;
  }
  if (!rc.finished_cleanly()) return {StatusCode::kCorrupt, "node order: bytes after its last node's"};
  return Status::Ok();
}

}  // namespace dtm
