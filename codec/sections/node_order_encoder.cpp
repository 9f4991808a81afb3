// The node order section written (spec/FORMAT.md §3.13): the encoder's side
// of node_order_coder.h.
#include <algorithm>

#include "codec/sections/node_order_coder.h"
#include "codec/sections/node_order_coder_shared.h"

namespace dtm {

std::vector<uint8_t> encode_node_order(const LevelEdges& edges, const NodeOrderFrame& frame, size_t vertices,
                                       std::span<const uint32_t> numbering) {
  RangeEncoder rc;
  NodeOrderModels models;
  const size_t nodes = frame.edge_of.size();
  UnvisitedVertices unnamed(nodes);
  size_t vertices_left = vertices, nodes_left = nodes;
  bool last_was_node = false, before_was_node = false;
  uint32_t last_node = NodeOrderFrame::kNoNode;
  std::vector<uint32_t> near;
  for (const uint32_t entry : numbering) {
    const bool is_node = entry >= vertices;
    if (vertices_left > 0 && nodes_left > 0)
      rc.encode(models.edge_for(last_was_node, before_was_node), is_node);
    if (is_node) {
      const auto node = static_cast<uint32_t>(entry - vertices);
      bool coded = false;
      if (last_node != NodeOrderFrame::kNoNode) {
        node_candidates(edges, frame, last_node, unnamed, near);
        if (!near.empty()) {
          const auto it = std::lower_bound(near.begin(), near.end(), node);
          const bool is_near = it != near.end() && *it == node;
          rc.encode(models.near_for(last_was_node, near.size()), is_near);
          if (is_near) rc.encode_index(static_cast<uint64_t>(it - near.begin()), near.size());
          coded = is_near;
        }
      }
      if (!coded) rc.encode_index(unnamed.rank(node), unnamed.left());
      unnamed.visit(node);
      last_node = node;
      --nodes_left;
    } else {
      --vertices_left;
    }
    before_was_node = last_was_node;
    last_was_node = is_node;
  }
  return rc.finish();
}

}  // namespace dtm
