// What the value coder's encoder (value_encoder.cpp) and decoder
// (value_decoder.cpp) share (spec/FORMAT.md §3.3): the adaptive models of
// a component and the bounds of a residual. Both sides must code with the
// same models; they are written here once.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>

#include "bitstream/range_coder.h"
#include "codec/sections/value_coder.h"

namespace dtm {

struct ValuePredictor::Models {
  AdaptiveBit nonzero[kValueSpreadContexts];
  AdaptiveBit negative[kValueSpreadContexts];
  // Unary magnitude class: "class > j" for j = 1, 2, ... (the last model
  // serves every larger j).
  AdaptiveBit more[kValueSpreadContexts][kValueClassModels];
  // The two bits under a magnitude's leading one, as a binary tree per class.
  AdaptiveBit mantissa[kValueClassModels][4];
};

using UInt128 = unsigned __int128;

// The largest magnitude class a residual can have: scaled values lie in
// [0, 2^65) (a 64-bit type's span), so |residual| < 2^65.
inline constexpr int kMaxClass = 65;

inline int bit_width128(UInt128 m) {
  const auto high = static_cast<uint64_t>(m >> 64);
  return high ? 64 + std::bit_width(high) : std::bit_width(static_cast<uint64_t>(m));
}

}  // namespace dtm
