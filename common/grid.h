// The integer grid shared by encoder and decoder (DESIGN.md §3.1): every
// geometric computation of the project runs on these integer coordinates,
// never on dequantized doubles. core/quantize.h puts input points on it.
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
  auto operator<=>(const GridPoint&) const = default;  // NOLINT(modernize-use-nullptr): clang-tidy 14 bug
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

// The points with these ids, in the ids' order.
inline std::vector<GridPoint> gather(std::span<const GridPoint> points, std::span<const uint32_t> ids) {
  std::vector<GridPoint> out;
  out.reserve(ids.size());
  for (uint32_t i : ids) out.push_back(points[i]);
  return out;
}

inline constexpr int kMinQBits = 1;
inline constexpr int kMaxQBits = 24;

}  // namespace dtm
