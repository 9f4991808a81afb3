#include "bitstream/range_coder.h"

namespace dtm {
namespace {
constexpr uint32_t kTop = 1u << 24;  // renormalize when the range falls below this
}

void RangeEncoder::shift_low() {
  if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
    const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
    uint8_t pending = cache_;
    do {
      if (first_byte_)
        first_byte_ = false;  // always zero: not sent
      else
        out_.push_back(static_cast<uint8_t>(pending + carry));
      pending = 0xFF;
    } while (--cache_size_ != 0);
    cache_ = static_cast<uint8_t>(static_cast<uint32_t>(low_) >> 24);
  }
  ++cache_size_;
  low_ = (low_ & 0x00FFFFFFu) << 8;  // bits 24-31 went to the cache above
}

void RangeEncoder::normalize() {
  while (range_ < kTop) {
    range_ <<= 8;
    shift_low();
  }
}

void RangeEncoder::encode(AdaptiveBit& model, bool bit) {
  const uint32_t bound = (range_ >> 16) * model.p0;
  if (!bit) {
    range_ = bound;
  } else {
    low_ += bound;
    range_ -= bound;
  }
  model.update(bit);
  normalize();
}

void RangeEncoder::encode_raw(uint64_t value, int n) {
  for (int i = n - 1; i >= 0; --i) {
    range_ >>= 1;
    if ((value >> i) & 1) low_ += range_;
    normalize();
  }
}

void RangeEncoder::encode_uniform(uint32_t value, uint32_t count) {
  range_ /= count;
  low_ += static_cast<uint64_t>(range_) * value;
  normalize();
}

void RangeEncoder::encode_index(uint64_t value, uint64_t count) {
  if (count <= 1) return;
  if (count <= kMaxUniform) {
    encode_uniform(static_cast<uint32_t>(value), static_cast<uint32_t>(count));
    return;
  }
  const int k = std::bit_width(count) - 1;
  const uint64_t u = (uint64_t{2} << k) - count;
  if (value < u)
    encode_raw(value, k);
  else
    encode_raw(value + u, k + 1);
}

std::vector<uint8_t> RangeEncoder::finish() {
  for (int i = 0; i < 5; ++i) shift_low();
  return std::move(out_);
}

RangeDecoder::RangeDecoder(std::span<const uint8_t> block) : block_(block) {
  for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next_byte();
}

void RangeDecoder::normalize() {
  while (range_ < kTop) {
    range_ <<= 8;
    code_ = (code_ << 8) | next_byte();
  }
}

bool RangeDecoder::decode(AdaptiveBit& model) {
  const uint32_t bound = (range_ >> 16) * model.p0;
  bool bit;
  if (code_ < bound) {
    range_ = bound;
    bit = false;
  } else {
    code_ -= bound;
    range_ -= bound;
    bit = true;
  }
  model.update(bit);
  normalize();
  return bit;
}

uint64_t RangeDecoder::decode_raw(int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) {
    range_ >>= 1;
    const bool bit = code_ >= range_;
    if (bit) code_ -= range_;
    v = (v << 1) | (bit ? 1 : 0);
    normalize();
  }
  return v;
}

Status RangeDecoder::decode_uniform(uint32_t count, uint32_t& value) {
  range_ /= count;
  const uint32_t v = code_ / range_;
  const bool valid = v < count;
  // Damaged: the state stays usable (range renormalized), the caller stops.
  if (valid) code_ -= v * range_;
  normalize();
  if (!valid) return {StatusCode::kCorrupt, "a uniform index is not below its count"};
  value = v;
  return Status::Ok();
}

Status RangeDecoder::decode_index(uint64_t count, uint64_t& value) {
  if (count <= 1) {
    value = 0;
    return Status::Ok();
  }
  if (count <= kMaxUniform) {
    uint32_t v = 0;
    DTM_RETURN_IF_ERROR(decode_uniform(static_cast<uint32_t>(count), v));
    value = v;
    return Status::Ok();
  }
  // Truncated binary: always a value below count.
  const int k = std::bit_width(count) - 1;
  const uint64_t u = (uint64_t{2} << k) - count;
  const uint64_t x = decode_raw(k);
  value = x < u ? x : ((x << 1) | decode_raw(1)) - u;
  return Status::Ok();
}

}  // namespace dtm
