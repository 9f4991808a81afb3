#include "core/importance.h"

#include <limits>

namespace dtm {

double importance(const LevelGeometry& L, uint32_t v) {
  const auto nbrs = L.neighbors.row(v);
  Int128 sum = 0;
  for (uint32_t u : nbrs) sum += L.mesh_volume6[u];
  if (L.mesh_volume6[v] <= 0) return std::numeric_limits<double>::infinity();
  return static_cast<double>(nbrs.size()) * static_cast<double>(sum) / static_cast<double>(L.mesh_volume6[v]);
}

}  // namespace dtm
