#include "codec/stream/layer_coder.h"

#include <algorithm>

#include "codec/stream/layer_coder_shared.h"
#include "common/bits_by_three.h"

namespace dtm {

SetCoderModels::SetCoderModels() : tables_(std::make_unique<Tables>()) {}

void SetCoderModels::enable_coordinate_reuse(int qbits) {
  tables_->used_sets.clear();
  tables_->reuse_qbits = qbits;
}
void SetCoderModels::note_points(std::span<const GridPoint> points) {
  for (const GridPoint& p : points) tables_->note(p);
}

SetCoderModels SetCoderModels::clone() const {
  SetCoderModels copy;
  *copy.tables_ = *tables_;
  return copy;
}

SetCoderModels::~SetCoderModels() = default;
SetCoderModels::SetCoderModels(SetCoderModels&&) noexcept = default;
SetCoderModels& SetCoderModels::operator=(SetCoderModels&&) noexcept = default;

MortonCode morton_encode(const GridPoint& p, int qbits) {
  if (qbits <= 21) {  // the common grids: three 64-bit spreads
    const uint64_t mask = (uint64_t{1} << qbits) - 1;
    return (spread_by_three(static_cast<uint32_t>(p.x) & mask) << 2) |
           (spread_by_three(static_cast<uint32_t>(p.y) & mask) << 1) |
           spread_by_three(static_cast<uint32_t>(p.z) & mask);
  }
  MortonCode code = 0;
  for (int i = qbits - 1; i >= 0; --i) {
    code = (code << 3) | (static_cast<unsigned>((p.x >> i) & 1) << 2) |
           (static_cast<unsigned>((p.y >> i) & 1) << 1) | static_cast<unsigned>((p.z >> i) & 1);
  }
  return code;
}

GridPoint morton_decode(MortonCode code, int qbits) {
  if (qbits <= 21) {
    const auto low = static_cast<uint64_t>(code);
    return {static_cast<int32_t>(gather_by_three(low >> 2)), static_cast<int32_t>(gather_by_three(low >> 1)),
            static_cast<int32_t>(gather_by_three(low))};
  }
  GridPoint p;
  for (int i = 0; i < qbits; ++i) {
    p.z |= static_cast<int32_t>((code >> (3 * i)) & 1) << i;
    p.y |= static_cast<int32_t>((code >> (3 * i + 1)) & 1) << i;
    p.x |= static_cast<int32_t>((code >> (3 * i + 2)) & 1) << i;
  }
  return p;
}

void merge_known(std::vector<MortonCode>& known, std::span<const GridPoint> added, int qbits) {
  const size_t old_size = known.size();
  known.reserve(old_size + added.size());  // exactly: 16 bytes a point, not twice as many
  for (const GridPoint& p : added) known.push_back(morton_encode(p, qbits));
  std::sort(known.begin() + old_size, known.end());
  std::inplace_merge(known.begin(), known.begin() + old_size, known.end());
}

}  // namespace dtm
