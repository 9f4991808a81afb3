#include "bitstream/coordinate_set.h"

#include <bit>
#include <stdexcept>

#include "common/status.h"

namespace dtm {

namespace {

// The position of the k-th (0-based) set bit of w; k < popcount(w).
int nth_set_bit(uint64_t w, uint64_t k) {
  for (; k > 0; --k) w &= w - 1;
  return std::countr_zero(w);
}

}  // namespace

CoordinateSet::CoordinateSet(int qbits) {
  DTM_CHECK(qbits >= 1 && qbits <= 24);
  const size_t blocks = qbits <= kBlockShift ? 1 : size_t{1} << (qbits - kBlockShift);
  blocks_.resize(blocks);
  tree_.assign(blocks + 1, 0);
  top_bit_ = std::bit_floor(blocks);
}

CoordinateSet::CoordinateSet(const CoordinateSet& other)
    : blocks_(other.blocks_.size()), tree_(other.tree_), top_bit_(other.top_bit_) {
  for (size_t b = 0; b < blocks_.size(); ++b)
    if (other.blocks_[b]) blocks_[b] = std::make_unique<Block>(*other.blocks_[b]);
}

CoordinateSet& CoordinateSet::operator=(const CoordinateSet& other) {
  if (this != &other) *this = CoordinateSet(other);
  return *this;
}

void CoordinateSet::insert(uint32_t value) {
  auto& block = blocks_[value >> kBlockShift];
  if (!block) block = std::make_unique<Block>();  // zeroed
  uint64_t& word = (*block)[(value >> 6) & 63];
  const uint64_t bit = uint64_t{1} << (value & 63);
  if (word & bit) return;
  word |= bit;
  for (size_t i = (value >> kBlockShift) + 1; i < tree_.size(); i += i & (~i + 1)) ++tree_[i];
}

bool CoordinateSet::contains(uint32_t value) const {
  const auto& block = blocks_[value >> kBlockShift];
  return block && (((*block)[(value >> 6) & 63] >> (value & 63)) & 1);
}

uint64_t CoordinateSet::count_below(uint64_t value) const {
  const uint64_t b = value >> kBlockShift;
  uint64_t count = 0;
  for (uint64_t i = std::min<uint64_t>(b, blocks_.size()); i > 0; i &= i - 1) count += tree_[i];
  if (b >= blocks_.size() || !blocks_[b]) return count;
  const Block& block = *blocks_[b];
  const uint64_t word = (value >> 6) & 63;
  for (uint64_t w = 0; w < word; ++w) count += std::popcount(block[w]);
  return count + std::popcount(block[word] & ((uint64_t{1} << (value & 63)) - 1));
}

uint64_t CoordinateSet::count_in(uint64_t lo, uint64_t hi) const {
  if (hi <= lo) return 0;
  const uint64_t b = lo >> kBlockShift;
  if (b != (hi - 1) >> kBlockShift) return count_below(hi) - count_below(lo);
  if (!blocks_[b]) return 0;
  const Block& block = *blocks_[b];
  const uint64_t first = (lo >> 6) & 63, last = ((hi - 1) >> 6) & 63;
  uint64_t count = 0;
  for (uint64_t w = first; w <= last; ++w) {
    uint64_t bits = block[w];
    if (w == first) bits &= ~uint64_t{0} << (lo & 63);
    if (w == last && (hi & 63) != 0) bits &= (uint64_t{1} << (hi & 63)) - 1;
    count += std::popcount(bits);
  }
  return count;
}

uint64_t CoordinateSet::find_block(uint64_t target, bool absent, uint64_t& before) const {
  // Fenwick descent: the node at pos + step covers the `step` blocks after pos.
  uint64_t pos = 0;
  before = 0;
  for (uint64_t step = top_bit_; step > 0; step >>= 1) {
    if (pos + step >= tree_.size()) continue;
    const uint64_t in_node = absent ? (step << kBlockShift) - tree_[pos + step] : tree_[pos + step];
    if (before + in_node <= target) {
      pos += step;
      before += in_node;
    }
  }
  return pos;
}

uint32_t CoordinateSet::select(uint64_t lo, uint64_t k) const {
  // First within lo's own block, from lo on.
  if (const auto& own = blocks_[lo >> kBlockShift]) {
    uint64_t rest = k;
    for (uint64_t w = (lo >> 6) & 63; w < 64; ++w) {
      uint64_t bits = (*own)[w];
      if (w == ((lo >> 6) & 63)) bits &= ~uint64_t{0} << (lo & 63);
      const uint64_t here = std::popcount(bits);
      if (rest < here)
        return static_cast<uint32_t>(((lo >> kBlockShift) << kBlockShift) + 64 * w + nth_set_bit(bits, rest));
      rest -= here;
    }
  }
  uint64_t before = 0;
  const uint64_t target = count_below(lo) + k;
  const uint64_t b = find_block(target, false, before);
  uint64_t rest = target - before;
  const Block& block = *blocks_[b];  // it holds the value, so it exists
  for (uint64_t w = 0;; ++w) {
    const uint64_t here = std::popcount(block[w]);
    if (rest < here) return static_cast<uint32_t>((b << kBlockShift) + 64 * w + nth_set_bit(block[w], rest));
    rest -= here;
  }
}

uint32_t CoordinateSet::select_absent(uint64_t lo, uint64_t k) const {
  // First within lo's own block, from lo on.
  const uint64_t block_start = (lo >> kBlockShift) << kBlockShift;
  if (const auto& own = blocks_[lo >> kBlockShift]) {
    uint64_t rest = k;
    for (uint64_t w = (lo >> 6) & 63; w < 64; ++w) {
      uint64_t gaps = ~(*own)[w];
      if (w == ((lo >> 6) & 63)) gaps &= ~uint64_t{0} << (lo & 63);
      const uint64_t here = std::popcount(gaps);
      if (rest < here) return static_cast<uint32_t>(block_start + 64 * w + nth_set_bit(gaps, rest));
      rest -= here;
    }
  } else if (lo + k < block_start + (uint64_t{1} << kBlockShift)) {
    return static_cast<uint32_t>(lo + k);
  }
  uint64_t before = 0;
  const uint64_t target = lo - count_below(lo) + k;
  const uint64_t b = find_block(target, true, before);
  uint64_t rest = target - before;
  if (!blocks_[b]) return static_cast<uint32_t>((b << kBlockShift) + rest);
  const Block& block = *blocks_[b];
  for (uint64_t w = 0;; ++w) {
    const uint64_t here = 64 - std::popcount(block[w]);
    if (rest < here) return static_cast<uint32_t>((b << kBlockShift) + 64 * w + nth_set_bit(~block[w], rest));
    rest -= here;
  }
}

}  // namespace dtm
