// What the candidate section's encoder (candidate_encoder.cpp) and decoder
// (candidate_decoder.cpp) share (spec/FORMAT.md §3.4): the models a section
// is coded with and the grid's bounds.
#pragma once

#include <cstdint>

#include "bitstream/range_coder.h"
#include "codec/sections/candidate_coder.h"

namespace dtm {

// A new point beside a candidate: one of 27 offsets, s = (dx + 1) + 3 (dy +
// 1) + 9 (dz + 1), coded as 5 bits down a binary tree (s >= 27 is corrupt).
inline constexpr int kOffsets = 27;
inline constexpr int kOffsetBits = 5;

struct CandidateModels {
  AdaptiveBit flag[kCandidateContexts];
  AdaptiveBit offset[1 << kOffsetBits];
};

// Whether (x, y, z) is a point of the grid of `qbits` bits.
bool candidate_inside_grid(int64_t x, int64_t y, int64_t z, int qbits);

}  // namespace dtm
