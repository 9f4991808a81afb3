// Quantization of input positions onto the grid, Draco-style (docs/ARCHITECTURE.md
// §3.1): coincident points are merged and counted, never dropped silently.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"

namespace dtm {

struct QuantizedPoints {
  Grid grid;
  // Distinct grid points in lexicographic order (x, then y, then z).
  std::vector<GridPoint> points;
  // For each input point, the index of its grid point in `points`.
  std::vector<uint32_t> input_to_point;
  // Input points that landed on an already occupied grid point.
  uint64_t duplicates_merged = 0;
};

// The largest side of the points' bounding box (what --box scales to).
double largest_extent(std::span<const InputPoint> points);

// Quantizes `input` onto a `qbits`-bit grid and merges coincident points.
// kInvalidInput for qbits out of range, an empty input, or non-finite
// coordinates.
StatusOr<QuantizedPoints> quantize(std::span<const InputPoint> input, int qbits);
// The same of the points times `scale` (each coordinate multiplied as a
// double, as a scaled copy would hold it), without the copy.
StatusOr<QuantizedPoints> quantize(std::span<const InputPoint> input, int qbits, double scale);

}  // namespace dtm
