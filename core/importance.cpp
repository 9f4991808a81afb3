#include "importance.h"

#include <limits>

namespace dtm {

double importance(const LevelGeometry& L, uint32_t v) {
  const auto nbrs = L.neighbors.row(v);
  double sum = 0;
  for (uint32_t u : nbrs) sum += L.mesh_volume[u];
  if (L.mesh_volume[v] <= 0) return std::numeric_limits<double>::infinity();
  return static_cast<double>(nbrs.size()) * sum / L.mesh_volume[v];
}

}  // namespace dtm
