#include "core/voxel_solid.h"

#include <cmath>

namespace dtm {

VoxelSolid::VoxelSolid(const VoxelMask& mask, const Grid& grid, double scale) : mask_(mask) {
  if (mask.lattice_offset) return;
  // Input position of grid point g: (grid.origin + grid.step g) / scale;
  // voxel coordinates: D^-1 (position - origin), D's columns the directions.
  const auto& d = mask.directions;
  const double a = d[0][0], b = d[1][0], c = d[2][0];
  const double e = d[0][1], f = d[1][1], g = d[2][1];
  const double h = d[0][2], i = d[1][2], j = d[2][2];
  const double det = a * (f * j - g * i) - b * (e * j - g * h) + c * (e * i - f * h);
  const std::array<std::array<double, 3>, 3> inverse = {
      {{(f * j - g * i) / det, (c * i - b * j) / det, (b * g - c * f) / det},
       {(g * h - e * j) / det, (a * j - c * h) / det, (c * e - a * g) / det},
       {(e * i - f * h) / det, (b * h - a * i) / det, (a * f - b * e) / det}}};
  for (int r = 0; r < 3; ++r) {
    double offset = 0;
    for (int k = 0; k < 3; ++k) {
      to_voxel_[r][k] = inverse[r][k] * grid.step / scale;
      offset += inverse[r][k] * (grid.origin[k] / scale - mask.origin[k]);
    }
    to_voxel_offset_[r] = offset;
  }
}

bool VoxelSolid::contains_point4(const std::array<int64_t, 3>& p) const {
  std::array<int64_t, 3> v;
  if (mask_.lattice_offset) {
    // Nearest voxel centre along each axis, half-way up: floor((p + 2) / 4).
    for (int a = 0; a < 3; ++a) {
      const int64_t q = p[a] + 2;
      v[a] = (q >= 0 ? q / 4 : -((-q + 3) / 4)) + (*mask_.lattice_offset)[a];
    }
  } else {
    for (int r = 0; r < 3; ++r) {
      double x = to_voxel_offset_[r];
      for (int k = 0; k < 3; ++k) x += to_voxel_[r][k] * (static_cast<double>(p[k]) / 4);
      v[r] = static_cast<int64_t>(std::floor(x + 0.5));
    }
  }
  return mask_.at(v[0], v[1], v[2]);
}

}  // namespace dtm
