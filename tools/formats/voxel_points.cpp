#include "voxel_points.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "format_error.h"

namespace dtm {

int bits_for_range(uint64_t range) {
  int q = 1;
  while (q < 63 && ((uint64_t{1} << q) - 1) < range) ++q;
  return q;
}

InputMesh voxel_points(const Volume& v, const VolumeOptions& asked, const std::string& path) {
  if (asked.threshold && asked.label) throw FormatError(path + ": give --threshold or --label, not both");
  if (asked.interior_step < 1) throw FormatError(path + ": the interior step must be at least 1");
  const uint64_t nx = v.sizes[0], ny = v.sizes[1], nz = v.sizes[2];
  // A mask (only 0s and 1s) needs neither: its solid is the 1s, and its
  // values say nothing the solid does not.
  const bool mask = !asked.threshold && !asked.label;
  if (mask)
    for (uint64_t at = 0; at < v.voxels(); ++at) {
      const double x = v.at(at % nx, at / nx % ny, at / (nx * ny));
      if (x != 0 && x != 1)
        throw FormatError(path +
                          ": a volume that is not a 0/1 mask needs --threshold T (solid: value >= T) or "
                          "--label L");
    }
  VolumeOptions o = mask ? VolumeOptions{std::nullopt, 1.0, asked.interior_step} : asked;
  // A float32 volume's values compared with the option as float32 holds it:
  // --label 2.3 is the voxels of value 2.3f, not none.
  if (v.type == ScalarType::kFloat32) {
    if (o.threshold) o.threshold = static_cast<float>(*o.threshold);
    if (o.label) o.label = static_cast<float>(*o.label);
  }
  std::vector<uint8_t> solid(v.voxels());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  uint64_t not_a_number = 0;
  for (uint64_t k = 0, at = 0; k < nz; ++k)
    for (uint64_t j = 0; j < ny; ++j)
      for (uint64_t i = 0; i < nx; ++i, ++at) {
        const double x = v.at(i, j, k);
        if (!std::isnan(x)) {
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        } else {
          ++not_a_number;
        }
        solid[at] = o.threshold ? x >= *o.threshold : x == *o.label;
      }
  auto is_solid = [&](int64_t i, int64_t j, int64_t k) {
    return i >= 0 && j >= 0 && k >= 0 && static_cast<uint64_t>(i) < nx && static_cast<uint64_t>(j) < ny &&
           static_cast<uint64_t>(k) < nz && solid[(k * ny + j) * nx + i];
  };
  const auto step = static_cast<uint64_t>(o.interior_step);
  std::vector<GridPoint> voxels;  // absolute indices
  std::vector<double> values;
  for (uint64_t k = 0, at = 0; k < nz; ++k)
    for (uint64_t j = 0; j < ny; ++j)
      for (uint64_t i = 0; i < nx; ++i, ++at) {
        if (!solid[at]) continue;
        const auto I = static_cast<int64_t>(i), J = static_cast<int64_t>(j), K = static_cast<int64_t>(k);
        const bool boundary = !is_solid(I - 1, J, K) || !is_solid(I + 1, J, K) || !is_solid(I, J - 1, K) ||
                              !is_solid(I, J + 1, K) || !is_solid(I, J, K - 1) || !is_solid(I, J, K + 1);
        if (boundary || (i % step == 0 && j % step == 0 && k % step == 0)) {
          voxels.push_back({static_cast<int32_t>(i), static_cast<int32_t>(j), static_cast<int32_t>(k)});
          values.push_back(v.at(i, j, k));
        }
      }
  if (voxels.empty() && mask)
    throw FormatError(path + ": the volume has no solid voxel (a 0/1 mask of 0s only)");
  if (voxels.empty()) {
    char text[200];
    std::snprintf(text, sizeof text, "%s %g selects no voxel (values range from %g to %g)",
                  o.threshold ? "--threshold" : "--label", o.threshold ? *o.threshold : *o.label, lo, hi);
    throw FormatError(path + ": " + text);
  }
  // Lexicographic (x, y, z) order, as QuantizedPoints requires.
  std::vector<uint32_t> order(voxels.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return voxels[a] < voxels[b]; });

  InputMesh out;
  VertexField value{"value", 1, {}, v.type};
  std::array<int32_t, 3> min{voxels[0].x, voxels[0].y, voxels[0].z}, max = min;
  for (const GridPoint& g : voxels) {
    min = {std::min(min[0], g.x), std::min(min[1], g.y), std::min(min[2], g.z)};
    max = {std::max(max[0], g.x), std::max(max[1], g.y), std::max(max[2], g.z)};
  }
  const auto& d = v.directions;
  const bool lattice = d[0][1] == 0 && d[0][2] == 0 && d[1][0] == 0 && d[1][2] == 0 && d[2][0] == 0 &&
                       d[2][1] == 0 && d[0][0] > 0 && d[0][0] == d[1][1] && d[0][0] == d[2][2];
  QuantizedPoints q;
  if (lattice) {
    const double s = d[0][0];
    q.grid.step = s;
    q.grid.origin = {v.origin[0] + min[0] * s, v.origin[1] + min[1] * s, v.origin[2] + min[2] * s};
    q.grid.qbits = bits_for_range(std::max({max[0] - min[0], max[1] - min[1], max[2] - min[2]}));
  }
  for (uint32_t idx : order) {
    const GridPoint& g = voxels[idx];
    value.values.push_back(values[idx]);
    if (lattice) {
      q.points.push_back({g.x - min[0], g.y - min[1], g.z - min[2]});
      out.points.push_back(q.grid.to_input(q.points.back()));
    } else {
      InputPoint p{v.origin[0], v.origin[1], v.origin[2]};
      for (int a = 0; a < 3; ++a) {
        const double t = a == 0 ? g.x : a == 1 ? g.y : g.z;
        p.x += t * d[a][0];
        p.y += t * d[a][1];
        p.z += t * d[a][2];
      }
      out.points.push_back(p);
    }
  }
  if (!mask) out.fields.push_back(std::move(value));
  if (not_a_number > 0)
    out.left_out.push_back(std::to_string(not_a_number) +
                           " voxels whose value is NaN (outside the solid: no " +
                           std::string(o.threshold ? "threshold" : "label") + " selects them)");
  VoxelMask& m = out.voxels.emplace();
  m.sizes = {nx, ny, nz};
  m.inside = std::move(solid);
  m.origin = v.origin;
  m.directions = d;
  if (lattice) m.lattice_offset = std::array<int64_t, 3>{min[0], min[1], min[2]};
  if (lattice) {
    q.input_to_point.resize(q.points.size());
    for (uint32_t i = 0; i < q.points.size(); ++i) q.input_to_point[i] = i;
    out.on_grid = std::move(q);
  }
  return out;
}

}  // namespace dtm
