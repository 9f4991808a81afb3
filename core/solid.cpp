#include "core/solid.h"

#include <algorithm>

#include "common/parallel_for.h"

namespace dtm {

std::vector<uint8_t> Solid::verdicts(const TetMesh& dt, std::span<const GridPoint> points) const {
  std::vector<uint8_t> out(dt.cells.size());
  constexpr size_t kBlock = 1024;
  parallel_for((out.size() + kBlock - 1) / kBlock,
               [&](size_t block) {
                 for (size_t c = block * kBlock; c < std::min(out.size(), block * kBlock + kBlock); ++c) {
                   const auto& k = dt.cells[c];
                   out[c] = region_of_centroid(points[k[0]], points[k[1]], points[k[2]], points[k[3]]);
                 }
               },
               4);
  return out;
}

}  // namespace dtm
