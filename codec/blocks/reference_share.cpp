#include "codec/blocks/reference_share.h"

#include <vector>

#include "codec/stream/layer_coder.h"

namespace dtm {

ReferenceShare::ReferenceShare(std::span<const GridPoint> points, int qbits, int rank, int ranks)
    : points_(points), qbits_(qbits), last_(rank + 1 >= ranks) {
  if (ranks <= 1 || points.empty()) return;
  // The cut before rank r: the key of the point N r / P in Morton order,
  // each found in what is left after the one before.
  std::vector<uint64_t> keys(points.size());
  for (size_t i = 0; i < points.size(); ++i) keys[i] = key(points[i]);
  auto from = keys.begin();
  for (int r = 1; r < ranks; ++r) {
    const auto at = keys.begin() + static_cast<std::ptrdiff_t>(points.size() * static_cast<size_t>(r) /
                                                               static_cast<size_t>(ranks));
    std::nth_element(from, at, keys.end());
    cuts_.push_back(*at);
    from = at;
  }
  lo_ = rank == 0 ? 0 : cuts_[static_cast<size_t>(rank - 1)];
  if (!last_) hi_ = cuts_[static_cast<size_t>(rank)];
}

uint64_t ReferenceShare::key(const GridPoint& p) const {
  const int shift = std::max(0, 3 * qbits_ - 64);
  return static_cast<uint64_t>(morton_encode(p, qbits_) >> shift);
}

}  // namespace dtm
