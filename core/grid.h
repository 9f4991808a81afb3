// Quantization of input positions onto one integer grid shared by encoder
// and decoder (DESIGN.md §3.1). Every geometric computation of the project
// runs on these integer coordinates, never on dequantized doubles.
#pragma once

#include <array>
#include <compare>
#include <cstdint>
#include <span>
#include <vector>

namespace dtm {

// A point of the q-bit grid: each coordinate in [0, 2^q - 1].
struct GridPoint {
  int32_t x = 0, y = 0, z = 0;
  auto operator<=>(const GridPoint&) const = default;
};

struct InputPoint {
  double x = 0, y = 0, z = 0;
};

// The grid, Draco-style: origin = minimum corner of the input's bounding box,
// one step for all axes = largest extent / (2^q - 1).
struct Grid {
  int qbits = 14;
  std::array<double, 3> origin{0, 0, 0};
  double step = 1.0;

  InputPoint to_input(const GridPoint& p) const {
    return {origin[0] + p.x * step, origin[1] + p.y * step, origin[2] + p.z * step};
  }
};

struct QuantizedPoints {
  Grid grid;
  // Distinct grid points in lexicographic order (x, then y, then z).
  std::vector<GridPoint> points;
  // For each input point, the index of its grid point in `points`.
  std::vector<uint32_t> input_to_point;
  // Input points that landed on an already occupied grid point.
  uint64_t duplicates_merged = 0;
};

inline constexpr int kMinQBits = 1;
inline constexpr int kMaxQBits = 24;

// The largest side of the points' bounding box (what --box scales to).
double largest_extent(std::span<const InputPoint> points);

// Quantizes `input` onto a `qbits`-bit grid and merges coincident points.
// Throws std::invalid_argument for qbits out of range, an empty input, or
// non-finite coordinates.
QuantizedPoints quantize(std::span<const InputPoint> input, int qbits);

}  // namespace dtm
