// The edge node section written (spec/FORMAT.md §3.11).
#include <bit>
#include <cassert>
#include <cstdlib>

#include "codec/sections/edge_node_coder.h"
#include "codec/sections/edge_node_coder_shared.h"

namespace dtm {

std::vector<uint8_t> encode_edge_nodes(const LevelEdges& edges, const EdgeNodeOffsets& nodes, int qbits,
                                       const EdgeNodePredictor* predictor) {
  RangeEncoder rc;
  EdgeNodeModels m;
  bool last_surface_moved = false;
  const int longest = longest_length(qbits, predictor != nullptr);
  constexpr std::array<int64_t, 3> kZero = {0, 0, 0};
  for (size_t e = 0; e < edges.corners.size(); ++e) {
    rc.encode(m.present, nodes.present[e] != 0);
    if (!nodes.present[e]) continue;
    const auto& d = nodes.offset[e];
    const std::array<int64_t, 3> p = predictor && edges.on_surface[e]
                                         ? predictor->offset(edges.corners[e][0], edges.corners[e][1])
                                         : kZero;
    const bool guessed = p != kZero;
    const bool moved = d != kZero;
    rc.encode(m.moved[moved_context(edges.on_surface[e], last_surface_moved, guessed)], moved);
    if (edges.on_surface[e]) last_surface_moved = moved;
    if (!moved) continue;
    const size_t set = guessed ? 1 : 0;
    for (size_t axis = 0; axis < 3; ++axis) {
      const int64_t r = d[axis] - p[axis];
      rc.encode(m.nonzero[set][axis], r != 0);
      if (r == 0) continue;
      rc.encode(m.negative[set][axis], r < 0);
      const auto magnitude = static_cast<uint64_t>(std::llabs(r));
      const int length = static_cast<int>(std::bit_width(magnitude)) - 1;
      assert(length <= longest);  // (offsets within reach, predictions within 2^(qbits + 1))
      for (int k = 0; k < length; ++k) rc.encode(m.longer[set][axis][static_cast<size_t>(k)], true);
      if (length < longest) rc.encode(m.longer[set][axis][static_cast<size_t>(length)], false);
      if (length > 0) rc.encode_raw(magnitude - (uint64_t{1} << length), length);
    }
  }
  return rc.finish();
}

}  // namespace dtm
