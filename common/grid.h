// The integer grid shared by encoder and decoder (docs/ARCHITECTURE.md §3.1): every
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

// An axis-aligned box of grid points, bounds included.
struct GridBox {
  std::array<int64_t, 3> lo{}, hi{};
  bool empty() const { return lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]; }
  bool contains(const GridPoint& p) const {
    return p.x >= lo[0] && p.x <= hi[0] && p.y >= lo[1] && p.y <= hi[1] && p.z >= lo[2] && p.z <= hi[2];
  }
  bool meets(const GridBox& o) const {
    for (int a = 0; a < 3; ++a)
      if (lo[a] > o.hi[a] || o.lo[a] > hi[a]) return false;
    return true;
  }
  // Grown by `margin` on every side, then clipped to the grid [0, 2^qbits).
  GridBox grown(int64_t margin, int qbits) const {
    GridBox b;
    const int64_t top = (int64_t{1} << qbits) - 1;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = lo[a] - margin < 0 ? 0 : lo[a] - margin;
      b.hi[a] = hi[a] + margin > top ? top : hi[a] + margin;
    }
    return b;
  }
};

inline constexpr int kMinQBits = 1;
inline constexpr int kMaxQBits = 24;

}  // namespace dtm
