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
  // come in runs.
  AdaptiveBit moved[3];
  // A moved node's offset, per axis: whether it is nonzero, its sign, and
  // its magnitude's bit length less one in unary (an Elias gamma code with
  // adaptive length bits; the bits below the leading one raw).
  AdaptiveBit nonzero[3];
  AdaptiveBit negative[3];
  AdaptiveBit longer[3][64];
};

// The context of an edge's moved bit.
inline int moved_context(bool on_surface, bool last_surface_moved) {
  return on_surface ? 1 + static_cast<int>(last_surface_moved) : 0;
}

}  // namespace dtm
