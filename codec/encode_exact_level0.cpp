#include "codec/encode_exact_level0.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/parallel_for.h"
#include "mesh/geometry.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

// The corners of the faces that one cell alone has: the solid's outer
// boundary (a reference of several regions measures its interfaces too).
uint64_t outer_boundary_vertices(size_t points, std::span<const std::array<uint32_t, 4>> cells) {
  std::vector<uint8_t> on(points, 0);
  for (const auto& face : boundary_triangles(cells))
    for (uint32_t v : face) on[v] = 1;
  return static_cast<uint64_t>(std::count(on.begin(), on.end(), uint8_t{1}));
}

}  // namespace

ExactLevel0 measure_exact_level0(std::span<const GridPoint> points,
                                 std::span<const std::array<uint32_t, 4>> cells, bool regions) {
  // Per block of cells, summed in block order: the figures do not depend on
  // how the blocks were shared out.
  constexpr size_t kBlock = 4096;
  struct Sums {
    double angle = 0, lowest = INFINITY, volume6 = 0;
  };
  std::vector<Sums> block((cells.size() + kBlock - 1) / kBlock);
  parallel_for(block.size(), [&](size_t b) {
    Sums& s = block[b];
    for (size_t c = b * kBlock; c < std::min(cells.size(), b * kBlock + kBlock); ++c) {
      const auto& k = cells[c];
      const double angle = smallest_solid_angle(points, k);
      s.angle += angle;
      s.lowest = std::min(s.lowest, angle);
      s.volume6 +=
          static_cast<double>(abs_six_volume(points[k[0]], points[k[1]], points[k[2]], points[k[3]]));
    }
  });
  ExactLevel0 out;
  out.cells = cells.size();
  double angle = 0, lowest = INFINITY, volume6 = 0;
  for (const Sums& s : block) {
    angle += s.angle;
    lowest = std::min(lowest, s.lowest);
    volume6 += s.volume6;
  }
  out.avg_min_solid_angle = out.cells ? angle / static_cast<double>(out.cells) : 0;
  out.min_solid_angle = out.cells ? lowest : 0;
  out.volume = volume6 / 6;
  if (regions) out.boundary_vertices = outer_boundary_vertices(points.size(), cells);
  return out;
}

void ExactLevel0::describe(LevelReport& level) const {
  LevelStats& s = level.stats;
  s.tetrahedra = cells;
  s.avg_min_solid_angle = avg_min_solid_angle;
  s.min_solid_angle = min_solid_angle;
  s.max_boundary_error = 0;
  s.mean_boundary_error = 0;
  if (s.reference_shape) {
    s.boundary_vertices = boundary_vertices ? *boundary_vertices : s.reference_shape->reference_vertices;
    s.reference_shape = ShapeFigures{{}, {}, {}, s.reference_shape->reference_vertices};
  }
  if (level.reference_error) level.reference_error = DistanceSummary{};
  if (level.reference_to_level) level.reference_to_level = DistanceSummary{};
  if (level.level_to_reference) level.level_to_reference = DistanceSummary{};
}

SolidDifference ExactLevel0::difference() const {
  SolidDifference d;
  d.second_volume = volume;
  d.shared_cells = cells;
  return d;
}

}  // namespace dtm
