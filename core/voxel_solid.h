// A scan's voxels as the solid its levels are carved to (spec/HIERARCHY.md
// §2.1): a cell is kept when the voxel holding its centroid is in the
// solid, one lookup. The voxel holding a point is the one whose centre is
// nearest along each axis (half-way: the higher index); a point outside
// the volume is outside the solid.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/grid.h"
#include "core/solid.h"

namespace dtm {

// Which voxels of a volume are in the solid, and where they are.
struct VoxelMask {
  std::array<uint64_t, 3> sizes{0, 0, 0};
  std::vector<uint8_t> inside;  // per voxel, x fastest: 1 if in the solid
  // The centre of voxel (i, j, k), in input units: origin + i d[0] + j d[1] + k d[2].
  std::array<double, 3> origin{0, 0, 0};
  std::array<std::array<double, 3>, 3> directions{};
  // The voxels are the grid itself (an isotropic, axis-aligned lattice):
  // grid point g is voxel g + lattice_offset, exactly.
  std::optional<std::array<int64_t, 3>> lattice_offset;

  bool at(int64_t i, int64_t j, int64_t k) const {
    return i >= 0 && j >= 0 && k >= 0 && static_cast<uint64_t>(i) < sizes[0] &&
           static_cast<uint64_t>(j) < sizes[1] && static_cast<uint64_t>(k) < sizes[2] &&
           inside[(static_cast<uint64_t>(k) * sizes[1] + static_cast<uint64_t>(j)) * sizes[0] +
                  static_cast<uint64_t>(i)] != 0;
  }
};

class VoxelSolid : public Solid {
 public:
  // `grid`: the encoder's grid, in input units multiplied by `scale`.
  // Without a lattice offset a grid point's voxel is found through the
  // volume's directions (inverted once), in doubles.
  VoxelSolid(const VoxelMask& mask, const Grid& grid, double scale);

  bool contains_point4(const std::array<int64_t, 3>& p) const override;

 private:
  const VoxelMask& mask_;
  // Without a lattice: voxel index = to_voxel_ (p / 4) + to_voxel_offset_.
  std::array<std::array<double, 3>, 3> to_voxel_{};
  std::array<double, 3> to_voxel_offset_{};
};

}  // namespace dtm
