#include "core/region_solid.h"

#include <algorithm>

#include "mesh/topology.h"

namespace dtm {
namespace {

// The cells of each region, by region index.
std::vector<std::vector<std::array<uint32_t, 4>>> cells_by_region(
    std::span<const std::array<uint32_t, 4>> cells, std::span<const uint8_t> region) {
  std::vector<std::vector<std::array<uint32_t, 4>>> out;
  for (size_t t = 0; t < cells.size(); ++t) {
    if (region[t] == 0) continue;
    if (out.size() < region[t]) out.resize(region[t]);
    out[region[t] - 1u].push_back(cells[t]);
  }
  return out;
}

}  // namespace

RegionSolid::RegionSolid(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells,
                         std::span<const uint8_t> region) {
  auto parts = cells_by_region(cells, region);
  parts_.resize(parts.size());
  for (size_t r = 0; r < parts.size(); ++r) {
    if (parts[r].empty()) continue;
    parts_[r].emplace(points, parts[r]);
    std::vector<std::array<uint32_t, 4>>().swap(parts[r]);
  }
}

uint8_t RegionSolid::region_point4(const std::array<int64_t, 3>& p) const {
  for (size_t r = 0; r < parts_.size(); ++r)
    if (parts_[r] && parts_[r]->contains_point4(p)) return static_cast<uint8_t>(r + 1);
  return 0;
}

std::vector<std::array<uint32_t, 3>> region_surface_triangles(std::span<const std::array<uint32_t, 4>> cells,
                                                              std::span<const uint8_t> region) {
  if (region.empty()) return boundary_triangles(cells);
  // Each region's boundary: the outer boundary's faces once, an interface's
  // twice (once from each side), kept once.
  std::vector<std::array<uint32_t, 3>> all;
  for (const auto& part : cells_by_region(cells, region)) {
    auto b = boundary_triangles(part);
    all.insert(all.end(), b.begin(), b.end());
  }
  return merged_region_boundaries(std::move(all));
}

std::vector<std::array<uint32_t, 3>> merged_region_boundaries(std::vector<std::array<uint32_t, 3>> all) {
  sort_as_boundary_triangles(all);
  auto key = [](std::array<uint32_t, 3> f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  all.erase(
      std::unique(all.begin(), all.end(), [&](const auto& a, const auto& b) { return key(a) == key(b); }),
      all.end());
  return all;
}

}  // namespace dtm
