// What the node label section's encoder and decoder share (spec/FORMAT.md
// §3.14): the models. Both sides must adapt them identically.
#pragma once

#include <array>

#include "bitstream/range_coder.h"

namespace dtm {

struct NodeLabelModels {
  // Whether a label is the one before it plus one, by whether the one
  // before it was.
  std::array<AdaptiveBit, 2> next;
  // Whether a gap is the last one's again (a constant stride), and a new
  // gap's sign (1: down).
  AdaptiveBit again;
  AdaptiveBit down;
  // A magnitude's bit length b (1 to 62; the first label's, less one, 0 to
  // 62): one bit per step, "more than j" for j = the least length on, each
  // its own model.
  std::array<AdaptiveBit, 63> longer;
};

}  // namespace dtm
