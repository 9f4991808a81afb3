#include "point_set_coder.h"

#include <algorithm>
#include <bit>

namespace dtm {
namespace {

class BitWriter {
 public:
  void bit(bool b) {
    if (used_ == 0) bytes_.push_back(0);
    if (b) bytes_.back() |= static_cast<uint8_t>(0x80u >> used_);
    used_ = (used_ + 1) & 7;
  }
  void bits(MortonCode v, int n) {  // n <= 128, most significant first
    for (int i = n - 1; i >= 0; --i) bit(((v >> i) & 1) != 0);
  }
  void ones(MortonCode n) {
    for (MortonCode i = 0; i < n; ++i) bit(true);
  }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
  int used_ = 0;
};

// Reads bits most significant first, 64 at a time where it can: a unary run
// is counted with one countl_one per word instead of bit by bit.
class BitReader {
 public:
  explicit BitReader(std::span<const uint8_t> bytes) : bytes_(bytes), size_(bytes.size() * 8) {}
  // Counts one bits up to the next zero bit and consumes them and it; gives
  // up (false) past `limit` ones or at the end of the input.
  bool unary(MortonCode limit, MortonCode& ones) {
    ones = 0;
    while (true) {
      if (pos_ >= size_) return false;
      const int run = std::countl_one(peek64());
      const size_t avail = size_ - pos_;
      if (static_cast<size_t>(run) < std::min<size_t>(64, avail)) {
        ones += run;
        pos_ += run + 1;
        return ones <= limit;
      }
      const size_t step = std::min<size_t>(64, avail);
      ones += step;
      pos_ += step;
      if (ones > limit) return false;
    }
  }
  bool bits(int n, MortonCode& v) {  // n <= 3 * 24
    if (pos_ + n > size_) return false;
    v = 0;
    while (n > 0) {
      const int take = std::min(n, 56);
      v = (v << take) | (peek64() >> (64 - take));
      pos_ += take;
      n -= take;
    }
    return true;
  }
  // True when only zero padding bits of the last byte remain.
  bool at_clean_end() const {
    if (pos_ > size_ || (pos_ + 7) / 8 != bytes_.size()) return false;
    if (pos_ % 8 == 0) return true;
    return (bytes_.back() & (0xFFu >> (pos_ % 8))) == 0;
  }

 private:
  // The next 64 bits from pos_, zeros past the end.
  uint64_t peek64() const {
    const size_t byte = pos_ >> 3;
    uint64_t word = 0;
    for (size_t i = 0; i < 8; ++i)
      word = (word << 8) | (byte + i < bytes_.size() ? bytes_[byte + i] : 0);
    const int shift = pos_ & 7;
    if (shift == 0) return word;
    const uint8_t next = byte + 8 < bytes_.size() ? bytes_[byte + 8] : 0;
    return (word << shift) | (next >> (8 - shift));
  }
  std::span<const uint8_t> bytes_;
  size_t size_;
  size_t pos_ = 0;
};

int bit_length(MortonCode v) {
  const uint64_t hi = static_cast<uint64_t>(v >> 64), lo = static_cast<uint64_t>(v);
  return hi ? 128 - std::countl_zero(hi) : 64 - std::countl_zero(lo);
}

}  // namespace

MortonCode morton_encode(const GridPoint& p, int qbits) {
  MortonCode code = 0;
  for (int i = qbits - 1; i >= 0; --i) {
    code = (code << 3) | (static_cast<unsigned>((p.x >> i) & 1) << 2) |
           (static_cast<unsigned>((p.y >> i) & 1) << 1) | static_cast<unsigned>((p.z >> i) & 1);
  }
  return code;
}

GridPoint morton_decode(MortonCode code, int qbits) {
  GridPoint p;
  for (int i = 0; i < qbits; ++i) {
    p.z |= static_cast<int32_t>((code >> (3 * i)) & 1) << i;
    p.y |= static_cast<int32_t>((code >> (3 * i + 1)) & 1) << i;
    p.x |= static_cast<int32_t>((code >> (3 * i + 2)) & 1) << i;
  }
  return p;
}

std::vector<uint8_t> encode_point_set(std::span<const GridPoint> points, int qbits) {
  std::vector<MortonCode> codes;
  codes.reserve(points.size());
  for (const GridPoint& p : points) codes.push_back(morton_encode(p, qbits));
  std::sort(codes.begin(), codes.end());
  std::vector<MortonCode> gaps(codes.size());
  for (size_t i = 0; i < codes.size(); ++i) gaps[i] = i == 0 ? codes[0] : codes[i] - codes[i - 1] - 1;

  // The Rice parameter that makes the payload smallest, searched around
  // log2 of the mean gap.
  int best_k = 0;
  if (!gaps.empty()) {
    MortonCode total = 0;
    for (MortonCode g : gaps) total += g;
    const int guess = bit_length(total / gaps.size());
    MortonCode best_bits = ~MortonCode{0};
    for (int k = std::max(0, guess - 3); k <= std::min(3 * qbits, guess + 2); ++k) {
      MortonCode bits = 0;
      for (MortonCode g : gaps) bits += (g >> k) + 1 + k;
      if (bits < best_bits) best_bits = bits, best_k = k;
    }
  }
  BitWriter w;
  w.bytes().push_back(static_cast<uint8_t>(best_k));
  // The k byte is whole, so bit writing starts on a fresh byte.
  std::vector<uint8_t> head = std::move(w.bytes());
  BitWriter body;
  for (MortonCode g : gaps) {
    body.ones(g >> best_k);
    body.bit(false);
    body.bits(g, best_k);
  }
  head.insert(head.end(), body.bytes().begin(), body.bytes().end());
  return head;
}

Status decode_point_set(std::span<const uint8_t> payload, int qbits, uint32_t count,
                        std::vector<GridPoint>& out) {
  if (payload.empty()) return {StatusCode::kCorrupt, "empty point-set payload"};
  if (payload.size() < min_payload_bytes(count))
    return {StatusCode::kCorrupt, "payload too short for its point count"};
  const int k = payload[0];
  if (k > 3 * qbits) return {StatusCode::kCorrupt, "Rice parameter out of range"};
  const MortonCode end = MortonCode{1} << (3 * qbits);  // codes are < end
  const MortonCode max_quotient = end >> k;
  BitReader r(payload.subspan(1));
  MortonCode next = 0;  // the smallest code the next point may have
  out.reserve(out.size() + count);
  for (uint32_t i = 0; i < count; ++i) {
    MortonCode quotient = 0;
    if (!r.unary(max_quotient, quotient))
      return {StatusCode::kCorrupt, quotient > max_quotient ? "point outside the grid"
                                                             : "point-set payload ends early"};
    MortonCode low = 0;
    if (!r.bits(k, low)) return {StatusCode::kCorrupt, "point-set payload ends early"};
    const MortonCode gap = (quotient << k) | low;
    if (gap >= end - next) return {StatusCode::kCorrupt, "point outside the grid"};
    const MortonCode code = next + gap;
    out.push_back(morton_decode(code, qbits));
    next = code + 1;
  }
  if (!r.at_clean_end()) return {StatusCode::kCorrupt, "trailing bits in a point-set payload"};
  return Status::Ok();
}

}  // namespace dtm
