#include "mesh/carving.h"

#include "mesh/geometry.h"

namespace dtm {

const char* to_string(AlphaKind kind) {
  switch (kind) {
    case AlphaKind::kPaper:
      return "paper";
    case AlphaKind::kFixed:
      return "fixed";
    case AlphaKind::kConvexHull:
      return "hull";
  }
  return "?";
}

double carving_radius(std::span<const GridPoint> points, const std::array<uint32_t, 4>& cell) {
  return canonical_circumradius({points[cell[0]], points[cell[1]], points[cell[2]], points[cell[3]]});
}

std::vector<uint8_t> carve(const TetMesh& dt, std::span<const GridPoint> points, double alpha) {
  std::vector<uint8_t> in_mesh(dt.cells.size());
  for (size_t k = 0; k < dt.cells.size(); ++k) in_mesh[k] = kept_by_alpha(points, dt.cells[k], alpha);
  return in_mesh;
}

}  // namespace dtm
