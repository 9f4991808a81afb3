#include "core/refill.h"

#include "mesh/carving.h"
#include "mesh/delaunay.h"

namespace dtm {

Refill refill_of(const LevelGeometry& L, uint32_t v) {
  Refill r;
  std::vector<GridPoint> link;
  std::vector<uint32_t> ids;
  for (uint32_t u : L.neighbors.row(v)) {
    link.push_back(L.points[u]);
    ids.push_back(u);
  }
  CavityFill fill = cavity_fill(link, ids, L.points[v]);
  r.cells = std::move(fill.cells);
  r.kept.resize(r.cells.size());
  for (size_t c = 0; c < r.cells.size(); ++c) r.kept[c] = kept_by_alpha(L.points, r.cells[c], L.alpha);
  return r;
}

}  // namespace dtm
