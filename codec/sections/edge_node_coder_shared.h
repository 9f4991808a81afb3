// What the edge node section's encoder and decoder share (spec/FORMAT.md
// §3.11): the models.
#pragma once

#include <cstdint>

#include "bitstream/range_coder.h"

namespace dtm {

struct EdgeNodeModels {
  AdaptiveBit present;
  // Whether the node is moved off the midpoint: an edge inside the solid
  // (0), one of its surface after a surface edge whose node was not moved
  // (1), after one whose node was (2): a curved boundary's moved nodes
  // come in runs. 19.0: a surface edge whose predicted offset is not 0
  // takes 3 and 4 instead of 1 and 2.
  AdaptiveBit moved[5];
  // A moved node's offset (19.0: its difference from the prediction), per
  // axis: whether it is nonzero, its sign, and its magnitude's bit length
  // less one in unary (an Elias gamma code with adaptive length bits; the
  // bits below the leading one raw). 19.0: set 1 for an edge whose
  // prediction is not (0, 0, 0), set 0 for the others (18.0: set 0).
  AdaptiveBit nonzero[2][3];
  AdaptiveBit negative[2][3];
  AdaptiveBit longer[2][3][64];
};

// The context of an edge's moved bit.
inline int moved_context(bool on_surface, bool last_surface_moved, bool predicted) {
  return on_surface ? 1 + 2 * static_cast<int>(predicted) + static_cast<int>(last_surface_moved) : 0;
}

// The most length bits of a magnitude: 18.0's offsets lie within
// edge_node_reach(), below 2^(qbits + 2); 19.0's differences from a
// prediction within 2^(qbits + 1) of the midpoint below 2^(qbits + 3).
inline int longest_length(int qbits, bool predicted) { return qbits + (predicted ? 2 : 1); }

}  // namespace dtm
