// The values one axis has taken so far in a stream: a bitmap over the 2^q
// coordinates in blocks of 4096 values, made when first written to, with a
// Fenwick tree of the blocks' counts, so that counting, ranking and selecting
// within any interval cost O(log 2^q) plus one block's 64 words, and within an
// interval inside one block (the common case: a lone point's node is about
// the sampling spacing wide) only the words it spans. The layer
// coder uses it to send a lone point's coordinate as "the i-th value already
// used here" (spec/FORMAT.md §3.1): meshes from grids, extrusions and CAD
// parts repeat coordinates far more often than chance.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace dtm {

class CoordinateSet {
 public:
  // Values in [0, 2^qbits), 1 <= qbits <= 24. Costs 12 bytes per block of
  // 4096 values (48 KiB at q = 24) plus 512 bytes per block in use.
  explicit CoordinateSet(int qbits);
  CoordinateSet(const CoordinateSet& other);
  CoordinateSet& operator=(const CoordinateSet& other);
  CoordinateSet(CoordinateSet&&) noexcept = default;
  CoordinateSet& operator=(CoordinateSet&&) noexcept = default;
  ~CoordinateSet() = default;

  void insert(uint32_t value);
  bool contains(uint32_t value) const;
  // Values in the set below `value` (any value up to 2^qbits).
  uint64_t count_below(uint64_t value) const;
  // Values in the set in [lo, hi).
  uint64_t count_in(uint64_t lo, uint64_t hi) const;
  // The k-th (0-based) value of the set at or above lo; k < count_in(lo, 2^qbits).
  uint32_t select(uint64_t lo, uint64_t k) const;
  // The k-th (0-based) value not in the set at or above lo, below 2^qbits.
  uint32_t select_absent(uint64_t lo, uint64_t k) const;

 private:
  static constexpr int kBlockShift = 12;  // 4096 values, 64 words
  using Block = std::array<uint64_t, 64>;

  // The block holding the target-th (0-based) present (or absent) value, and
  // how many such values the blocks before it hold.
  uint64_t find_block(uint64_t target, bool absent, uint64_t& before) const;

  std::vector<std::unique_ptr<Block>> blocks_;
  std::vector<uint32_t> tree_;  // Fenwick tree over the blocks' counts, 1-based
  uint64_t top_bit_ = 0;        // largest power of two <= blocks_.size()
};

}  // namespace dtm
