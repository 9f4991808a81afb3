// A solid of several regions (materials): the input's tetrahedra, each
// labelled with its region (spec/HIERARCHY.md §2.2). A cell of a level is
// kept when its centroid lies in the union, as with one region
// (reference_solid.h), and takes the region whose tetrahedra hold the
// centroid; a centroid on an interface, in the closed sets of two regions,
// takes the first of them (the lowest index). Both verdicts are exact.
//
// Held as one ReferenceSolid a region: a region's boundary is its share of
// the outer boundary and its interfaces, so that each answers mostly by one
// lookup of its classified grid.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/grid.h"
#include "core/reference_solid.h"
#include "core/solid.h"

namespace dtm {

// The most regions a stream carries: a cell's region is a byte, 0 meaning
// outside the solid (spec/FORMAT.md §2.2).
inline constexpr size_t kMaxRegions = 255;

class RegionSolid : public Solid {
 public:
  // `region[t]`, 1 .. kMaxRegions: the region of `cells[t]` plus one (the
  // index of its label in the stream's region table, plus one). `points`
  // must outlive the solid; the cells need not.
  RegionSolid(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> cells,
              std::span<const uint8_t> region);

  bool contains_point4(const std::array<int64_t, 3>& p) const override { return region_point4(p) != 0; }
  uint8_t region_point4(const std::array<int64_t, 3>& p) const override;
  size_t regions() const { return parts_.size(); }

 private:
  // Per region index (label - 1); a region with no cell is not made.
  std::vector<std::optional<ReferenceSolid>> parts_;
};

// The reference's surfaces the levels are measured against: the faces of
// exactly one of `cells` (the outer boundary) and the faces between two
// cells of different regions (each interface face once), sorted as
// boundary_triangles() sorts them. Without regions, boundary_triangles().
std::vector<std::array<uint32_t, 3>> region_surface_triangles(std::span<const std::array<uint32_t, 4>> cells,
                                                              std::span<const uint8_t> region);
// The same from each region's boundary_triangles(), concatenated in the
// regions' order (as the ranks of a run find them, a region at a time).
std::vector<std::array<uint32_t, 3>> merged_region_boundaries(std::vector<std::array<uint32_t, 3>> all);

}  // namespace dtm
