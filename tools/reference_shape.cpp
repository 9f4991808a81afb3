#include "reference_shape.h"

#include <algorithm>

#include "tools/formats/surface_writers.h"

namespace dtm {
namespace {

std::vector<GridPoint> vertices_of(std::span<const std::array<uint32_t, 3>> triangles,
                                   std::span<const GridPoint> points) {
  std::vector<uint32_t> ids;
  for (const auto& t : triangles) ids.insert(ids.end(), t.begin(), t.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<GridPoint> out;
  out.reserve(ids.size());
  for (uint32_t v : ids) out.push_back(points[v]);
  return out;
}

}  // namespace

ReferenceShape::ReferenceShape(std::span<const std::array<uint32_t, 4>> tets, const QuantizedPoints& q) {
  for (const auto& t : tets) {
    std::array<uint32_t, 4> g{q.input_to_point[t[0]], q.input_to_point[t[1]], q.input_to_point[t[2]],
                              q.input_to_point[t[3]]};
    std::array<uint32_t, 4> s = g;
    std::sort(s.begin(), s.end());
    if (std::adjacent_find(s.begin(), s.end()) == s.end()) tets_.push_back(g);
  }
  // Orientation does not matter for distances: no need to fix the input's.
  boundary_ = boundary_triangles(tets_);
  boundary_vertices_ = vertices_of(boundary_, q.points);
}

DistanceSummary ReferenceShape::distance(std::span<const std::array<uint32_t, 4>> cells,
                                         std::span<const GridPoint> points) const {
  const auto level_boundary = boundary_triangles(cells);
  const auto level_vertices = vertices_of(level_boundary, points);
  const DistanceSummary to_level = distance_to_surface(points, level_boundary, boundary_vertices_);
  const DistanceSummary to_reference = distance_to_surface(points, boundary_, level_vertices);
  const double n = static_cast<double>(boundary_vertices_.size() + level_vertices.size());
  DistanceSummary out;
  out.max = std::max(to_level.max, to_reference.max);
  out.mean = n > 0 ? (to_level.mean * boundary_vertices_.size() + to_reference.mean * level_vertices.size()) / n : 0;
  return out;
}

}  // namespace dtm
