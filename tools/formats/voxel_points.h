// The solid of a scalar volume as a point set: the voxels a threshold or a
// label selects, every boundary voxel (one of its 6 neighbours unselected or
// outside the volume) and the interior voxels whose indices are all multiples
// of `interior_step`. On an isotropic, axis-aligned lattice the lattice is
// the quantization grid itself (lossless); otherwise the voxel centres are
// placed at their physical positions and quantized like any point set.
#pragma once

#include <optional>
#include <string>

#include "input_mesh.h"
#include "nrrd.h"

namespace dtm {

struct VolumeOptions {
  std::optional<double> threshold;  // solid: value >= threshold
  std::optional<double> label;      // solid: value == label
  int interior_step = 1;            // keep interior voxels with i, j, k all multiples of this
};

// Without a selection the volume must be a 0/1 mask: its solid is the 1s
// and it has no field; with one, the selected voxels' values are the field
// `value`. Throws FormatError naming `path` when both selections are given,
// none for a volume that is not a mask, or when nothing is selected.
InputMesh voxel_points(const Volume& volume, const VolumeOptions& options, const std::string& path);

// The smallest q with 2^q - 1 >= range (at least 1).
int bits_for_range(uint64_t range);

}  // namespace dtm
