// A binary range coder (the carry-less-with-cache design of LZMA) with
// adaptive bit models. Each layer's payload is one range-coded block; the
// models live outside the coder, so they can carry what they learnt from one
// layer into the next.
//
// Block: the encoder's bytes after its first output byte (always zero, so it
// is not sent), including the four bytes of the final flush. The decoder
// reads exactly those bytes; reading past the end yields zeros and is
// reported by overran(), and a block is valid only if the decoder ends having
// read every byte and no more (finished_cleanly()).
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "common/status.h"

namespace dtm {

// P(bit = 0) in 1/65536 units, adapting faster while young: the first
// observations move it like a count (rate 1/(n+2)), later ones by 1/128 at
// most, so that a model follows slowly drifting statistics across layers.
struct AdaptiveBit {
  uint16_t p0 = 32768;
  uint8_t seen = 0;

  void update(bool bit) {
    const int rate = std::min(7, static_cast<int>(std::bit_width(seen + 2u)));
    if (bit)
      p0 -= p0 >> rate;
    else
      p0 += (65536 - p0) >> rate;
    if (seen < 255) ++seen;
  }
};

// The largest count encode_uniform takes: the range (at least 2^24 between
// symbols) must leave at least 2^8 per value.
inline constexpr uint32_t kMaxUniform = uint32_t{1} << 16;

class RangeEncoder {
 public:
  void encode(AdaptiveBit& model, bool bit);
  // n raw bits of `value`, most significant first (each costs exactly one bit).
  void encode_raw(uint64_t value, int n);
  // `value` in [0, count), all equally likely: log2(count) bits, to within
  // count / 2^24 of a bit. 2 <= count <= kMaxUniform.
  void encode_uniform(uint32_t value, uint32_t count);
  // `value` in [0, count), count >= 1 (nothing is coded for 1): a uniform
  // symbol, or truncated binary in raw bits when count > kMaxUniform
  // (spec/FORMAT.md §3.1, "uniform index").
  void encode_index(uint64_t value, uint64_t count);
  // Flushes and returns the block.
  std::vector<uint8_t> finish();

 private:
  void normalize();
  void shift_low();
  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t cache_size_ = 1;
  bool first_byte_ = true;  // the always-zero first byte is dropped
  std::vector<uint8_t> out_;
};

class RangeDecoder {
 public:
  explicit RangeDecoder(std::span<const uint8_t> block);
  bool decode(AdaptiveBit& model);
  uint64_t decode_raw(int n);
  // A value coded by encode_uniform; kCorrupt if the bytes do not hold one
  // (only a damaged block does that; the decoder stays usable).
  Status decode_uniform(uint32_t count, uint32_t& value);
  // A value coded by encode_index; kCorrupt if the bytes do not hold one.
  Status decode_index(uint64_t count, uint64_t& value);
  // Bytes past the end of the block were needed.
  bool overran() const { return pos_ > block_.size(); }
  // Every byte of the block was read, none past it, and the final flush
  // matches: what a block written by RangeEncoder ends like.
  bool finished_cleanly() const { return pos_ == block_.size() && code_ == 0; }

 private:
  uint8_t next_byte() { return pos_ < block_.size() ? block_[pos_++] : (++pos_, 0); }
  void normalize();
  std::span<const uint8_t> block_;
  size_t pos_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint32_t code_ = 0;
};

}  // namespace dtm
