#include "core/reference_shape.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh/topology.h"

namespace dtm {
namespace {

std::vector<uint32_t> vertex_ids_of(std::span<const std::array<uint32_t, 3>> triangles) {
  std::vector<uint32_t> ids;
  for (const auto& t : triangles) ids.insert(ids.end(), t.begin(), t.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

// The input's tetrahedra on the grid, without those quantization collapsed.
std::vector<std::array<uint32_t, 4>> collapsed_dropped(std::span<const std::array<uint32_t, 4>> tets,
                                                       const QuantizedPoints& q) {
  std::vector<std::array<uint32_t, 4>> out;
  for (const auto& t : tets) {
    std::array<uint32_t, 4> g{q.input_to_point[t[0]], q.input_to_point[t[1]], q.input_to_point[t[2]],
                              q.input_to_point[t[3]]};
    std::array<uint32_t, 4> s = g;
    std::sort(s.begin(), s.end());
    if (std::adjacent_find(s.begin(), s.end()) == s.end()) out.push_back(g);
  }
  return out;
}

}  // namespace

// Orientation does not matter for distances: no need to fix the input's.
ReferenceShape::ReferenceShape(std::span<const std::array<uint32_t, 4>> tets, const QuantizedPoints& q)
    : tets_(collapsed_dropped(tets, q)),
      boundary_(boundary_triangles(tets_)),
      boundary_vertices_(gather(q.points, vertex_ids_of(boundary_))),
      reference_surface_(q.points, boundary_),
      to_level_(boundary_vertices_),
      to_reference_(q.points.size(), std::numeric_limits<double>::quiet_NaN()) {}

ReferenceShape::TwoWay ReferenceShape::distance(std::span<const std::array<uint32_t, 4>> cells,
                                                std::span<const GridPoint> points) {
  const auto level_boundary = boundary_triangles(cells);
  const DistanceSummary to_level =
      boundary_vertices_.empty() ? DistanceSummary{} : to_level_.measure(points, {}, level_boundary);
  const std::vector<uint32_t> level_ids = vertex_ids_of(level_boundary);
  std::vector<uint32_t> unmeasured;
  for (uint32_t v : level_ids)
    if (std::isnan(to_reference_[v])) unmeasured.push_back(v);
  const std::vector<double> fresh = reference_surface_.squared_distances(gather(points, unmeasured));
  for (size_t i = 0; i < unmeasured.size(); ++i) to_reference_[unmeasured[i]] = fresh[i];
  std::vector<double> squared;
  squared.reserve(level_ids.size() + level_boundary.size());
  for (uint32_t v : level_ids) squared.push_back(to_reference_[v]);
  // A point inside each triangle too: a flat triangle between two surface
  // vertices can cut across a concavity its corners do not see.
  std::vector<std::array<double, 3>> centroids;
  centroids.reserve(level_boundary.size());
  for (const auto& t : level_boundary) {
    const GridPoint &a = points[t[0]], &b = points[t[1]], &c = points[t[2]];
    centroids.push_back({(double{1} * a.x + b.x + c.x) / 3, (double{1} * a.y + b.y + c.y) / 3,
                         (double{1} * a.z + b.z + c.z) / 3});
  }
  const std::vector<double> centroid_squared = reference_surface_.squared_distances(centroids);
  squared.insert(squared.end(), centroid_squared.begin(), centroid_squared.end());
  const DistanceSummary to_reference = summarize_squared(squared);
  const double n_level = static_cast<double>(squared.size());
  const double n = static_cast<double>(boundary_vertices_.size()) + n_level;
  TwoWay out;
  out.to_level = to_level;
  out.to_reference = to_reference;
  out.both.max = std::max(to_level.max, to_reference.max);
  out.both.mean = n > 0 ? (to_level.mean * boundary_vertices_.size() + to_reference.mean * n_level) / n : 0;
  return out;
}

}  // namespace dtm
