// The importance value of an interior vertex (seed paper eq. 2.4):
//   IP(n) = degree(n) * sum over neighbours i of vol(i) / vol(n),
// with vol(x) the total volume of the M_l cells incident to x. Small, dense
// regions score high and are kept; the greedy removal takes ascending IP.
#pragma once

#include <cstdint>

#include "core/level.h"

namespace dtm {

double importance(const LevelGeometry& level, uint32_t vertex);

}  // namespace dtm
