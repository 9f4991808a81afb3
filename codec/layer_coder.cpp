#include "codec/layer_coder.h"

#include <algorithm>

#include "codec/layer_coder_contexts.h"

namespace dtm {

SetCoderModels::SetCoderModels() : tables_(std::make_unique<Tables>()) {}

void SetCoderModels::enable_coordinate_reuse(int qbits) {
  tables_->used_sets.clear();
  tables_->reuse_qbits = qbits;
}
SetCoderModels::~SetCoderModels() = default;
SetCoderModels::SetCoderModels(SetCoderModels&&) noexcept = default;
SetCoderModels& SetCoderModels::operator=(SetCoderModels&&) noexcept = default;

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

void merge_known(std::vector<MortonCode>& known, std::span<const GridPoint> added, int qbits) {
  const size_t old_size = known.size();
  for (const GridPoint& p : added) known.push_back(morton_encode(p, qbits));
  std::sort(known.begin() + old_size, known.end());
  std::inplace_merge(known.begin(), known.begin() + old_size, known.end());
}

}  // namespace dtm
