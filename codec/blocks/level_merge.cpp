#include "codec/blocks/level_merge.h"

#include <algorithm>
#include <cmath>

namespace dtm {

MergedLevel merge_blocks(std::vector<BlockAnalysis>& analysis, int level, BrickedLevel& out) {
  LevelStats& s = out.stats;
  DistanceSums to_level, to_reference;
  double quality_sum = 0, quality_min = INFINITY;
  MergedLevel m;
  {
    size_t triangles = 0, vertices = 0, squared = 0, owned_boundary = 0;
    for (const BlockAnalysis& a : analysis) {
      triangles += a.surface_triangles.size(), vertices += a.surface_vertices.size();
      squared += a.reference_squared.size(), owned_boundary += a.boundary.size();
    }
    m.record.triangles.reserve(triangles);
    m.record.vertices.reserve(vertices);
    m.reference_squared.reserve(squared);
    m.boundary.reserve(owned_boundary);
  }
  for (BlockAnalysis& a : analysis) {
    const BlockFigures& f = a.figures;
    s.boundary_vertices += f.boundary_vertices;
    s.tetrahedra += f.cells;
    quality_sum += f.quality_sum;
    quality_min = std::min(quality_min, f.quality_min);
    to_level.add(f.to_level);
    to_reference.add(f.to_reference);
    out.cell_hash += f.cell_hash;
    m.dropped_thick += f.dropped_thick;
    m.dropped_thick_radius = std::max(m.dropped_thick_radius, f.dropped_thick_radius);
    out.take_sections(a);
    m.record.triangles.insert(m.record.triangles.end(), a.surface_triangles.begin(),
                              a.surface_triangles.end());
    m.record.vertices.insert(m.record.vertices.end(), a.surface_vertices.begin(), a.surface_vertices.end());
    m.reference_squared.insert(m.reference_squared.end(), a.reference_squared.begin(),
                               a.reference_squared.end());
    m.boundary.insert(m.boundary.end(), a.boundary.begin(), a.boundary.end());
    m.carved.insert(m.carved.end(), a.carved.begin(), a.carved.end());
    BlockAnalysis kept;
    kept.figures = a.figures;
    kept.chosen = std::move(a.chosen);
    a = std::move(kept);
  }
  std::sort(m.record.triangles.begin(), m.record.triangles.end());
  std::sort(m.record.vertices.begin(), m.record.vertices.end());
  std::sort(m.reference_squared.begin(), m.reference_squared.end());
  std::sort(m.boundary.begin(), m.boundary.end());
  s.avg_min_solid_angle = s.tetrahedra ? quality_sum / static_cast<double>(s.tetrahedra) : 0;
  s.min_solid_angle = s.tetrahedra ? quality_min : 0;
  if (to_level.count + to_reference.count > 0) {
    ShapeFigures shape;
    shape.to_level = {to_level.max, to_level.count ? to_level.sum / to_level.count : 0};
    shape.to_reference = {to_reference.max, to_reference.count ? to_reference.sum / to_reference.count : 0};
    shape.both = {
        std::max(to_level.max, to_reference.max),
        (to_level.sum + to_reference.sum) / static_cast<double>(to_level.count + to_reference.count)};
    s.reference_shape = shape;
    m.reference_boundary_vertices = to_level.count;
    s.max_boundary_error = shape.to_level.max;
    s.mean_boundary_error = shape.to_level.mean;
  } else if (level == 0) {
    s.reference_shape = ShapeFigures{};  // level 0 is its own reference
  }
  return m;
}

bool level_quality_met(std::span<const BlockQuality> blocks) {
  if (std::all_of(blocks.begin(), blocks.end(), [](const BlockQuality& b) { return b.met; })) return true;
  double sum = 0, floor_sum = 0;
  for (const BlockQuality& b : blocks) {
    sum += b.sum;
    floor_sum += b.floor * static_cast<double>(b.cells);
  }
  return sum >= floor_sum;
}

}  // namespace dtm
