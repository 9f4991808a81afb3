// What the node order section's encoder and decoder share (spec/FORMAT.md
// §3.13): the models and the candidates a step offers. Both sides must
// compute them identically.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "bitstream/range_coder.h"
#include "codec/sections/node_order_coder.h"
#include "codec/sections/vertex_order_coder_shared.h"

namespace dtm {

struct NodeOrderModels {
  // Whether the next node is an edge node, by the kinds of the two before
  // it (an edge node 1, a vertex or none 0): the first bit the one before.
  AdaptiveBit edge[4];
  AdaptiveBit& edge_for(bool last, bool before_last) { return edge[(last ? 2 : 0) + (before_last ? 1 : 0)]; }
  // Whether the next edge node is one of the candidates, by whether the
  // node before it was an edge node and how many candidates there are (1,
  // 2-3, 4-7, 8-15, 16+).
  AdaptiveBit near[2][5];
  AdaptiveBit& near_for(bool after_edge_node, size_t candidates) {
    size_t k = 0;
    while (k < 4 && (size_t{2} << k) <= candidates) ++k;
    return near[after_edge_node ? 1 : 0][k];
  }
};

// The candidates for the node after node `last`: the unnamed nodes on the
// edges of the kept cells that have last's edge, ascending, once each.
inline void node_candidates(const LevelEdges& edges, const NodeOrderFrame& frame, uint32_t last,
                            const UnvisitedVertices& unnamed, std::vector<uint32_t>& out) {
  out.clear();
  for (uint32_t cell : frame.cells_of_edge.row(frame.edge_of[last]))
    for (uint32_t e : edges.cell_edges[cell])
      if (const uint32_t node = frame.node_of[e]; node != NodeOrderFrame::kNoNode && !unnamed.visited(node))
        out.push_back(node);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace dtm
