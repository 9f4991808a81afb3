// The two fixed point sets the section targets (carving, values) decode
// over: a 4x4x4 block (cospherical everywhere) and 300 pseudo-random points
// of a 7-bit grid.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "common/grid.h"

inline const std::vector<dtm::GridPoint>& fuzz_point_set(bool random) {
  static const std::vector<dtm::GridPoint> block = [] {
    std::vector<dtm::GridPoint> p;
    for (int x = 0; x < 4; ++x)
      for (int y = 0; y < 4; ++y)
        for (int z = 0; z < 4; ++z) p.push_back({x, y, z});
    return p;
  }();
  static const std::vector<dtm::GridPoint> cloud = [] {
    std::vector<dtm::GridPoint> p;
    uint32_t s = 12345;
    auto next = [&] { return static_cast<int32_t>((s = s * 1103515245u + 12345u) >> 25); };
    for (int i = 0; i < 300; ++i) p.push_back({next(), next(), next()});
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
    return p;
  }();
  return random ? cloud : block;
}
