#include "codec/blocks/reference_share.h"

#include <vector>

#include "codec/stream/layer_coder.h"

namespace dtm {

ReferenceShare::ReferenceShare(std::span<const GridPoint> points, int qbits, int rank, int ranks)
    : points_(points), qbits_(qbits), last_(rank + 1 >= ranks) {
  if (ranks <= 1 || points.empty()) return;
  // The cut before rank r: the key of the point N r / P in Morton order.
  std::vector<uint64_t> keys(points.size());
  for (size_t i = 0; i < points.size(); ++i) keys[i] = key(points[i]);
  const auto cut = [&](int r) {
    const size_t at = points.size() * static_cast<size_t>(r) / static_cast<size_t>(ranks);
    std::nth_element(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(at), keys.end());
    return keys[at];
  };
  lo_ = rank == 0 ? 0 : cut(rank);
  if (!last_) hi_ = cut(rank + 1);
}

uint64_t ReferenceShare::key(const GridPoint& p) const {
  const int shift = std::max(0, 3 * qbits_ - 64);
  return static_cast<uint64_t>(morton_encode(p, qbits_) >> shift);
}

}  // namespace dtm
