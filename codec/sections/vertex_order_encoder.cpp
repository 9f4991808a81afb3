// The vertex order section written (spec/FORMAT.md §3.9): the encoder's side
// of vertex_order_coder.h.
#include <algorithm>

#include "codec/sections/vertex_order_coder.h"
#include "codec/sections/vertex_order_coder_shared.h"

namespace dtm {

std::vector<uint8_t> encode_vertex_order(const Csr& neighbours, std::span<const uint32_t> order) {
  RangeEncoder rc;
  VertexOrderModels models;
  UnvisitedVertices unvisited(neighbours.rows());
  std::vector<uint32_t> near;
  for (size_t k = 0; k < order.size(); ++k) {
    const uint32_t v = order[k];
    bool coded = false;
    if (k > 0) {
      unvisited_neighbours(neighbours, order[k - 1], unvisited, near);
      if (!near.empty()) {
        const auto it = std::find(near.begin(), near.end(), v);
        const bool is_near = it != near.end();
        rc.encode(models.near_for(near.size()), is_near);
        if (is_near) rc.encode_index(static_cast<uint64_t>(it - near.begin()), near.size());
        coded = is_near;
      }
    }
    if (!coded) rc.encode_index(unvisited.rank(v), unvisited.left());
    unvisited.visit(v);
  }
  return rc.finish();
}

}  // namespace dtm
