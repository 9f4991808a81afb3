// Which input tetrahedron gives each cell of level 0 its cell data (format
// 10.0, docs/VALUES.md): a level-0 cell that is one of the input's takes
// its own values, exactly; another (level 0 is the Delaunay
// tetrahedralization of the input's points, carved to its solid, which
// differs from the input's cells where the mesher's were not Delaunay:
// 4.5% of a gmsh part's) takes those of the input tetrahedron that holds
// its centroid, as a cell takes its region (core/region_solid.h), looked
// for among the input tetrahedra sharing a vertex with it. Where none of
// those holds it (a cell whose centroid lies farther off), the one of them
// whose centroid is nearest. An encoder's policy: the decoder only reads
// the values.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/csr.h"
#include "common/grid.h"

namespace dtm {

struct CellSources {
  std::vector<uint32_t> tetrahedron;  // per cell, an index into the reference tetrahedra
  uint64_t exact = 0;                 // cells that are input tetrahedra
  uint64_t nearest = 0;               // cells given the nearest of their vertices' tetrahedra
};

// The reference tetrahedra by vertex, asked cell by cell (from any thread):
// what a bricked encoder's blocks ask for the level-0 cells they own
// (codec/blocks/block_levels.h). Holds 4 bytes per corner of a reference
// tetrahedron and one per point; the points and tetrahedra are the caller's.
class CellSourceIndex {
 public:
  CellSourceIndex(std::span<const GridPoint> points, std::span<const std::array<uint32_t, 4>> reference);
  enum class Found : uint8_t { kExact, kHolding, kNearest };
  // The reference tetrahedron that gives `cell` its values (the least index
  // among equals), and how it was found. `cell` names `points` and shares a
  // vertex with some reference tetrahedron.
  uint32_t source(const std::array<uint32_t, 4>& cell, Found& found) const;

 private:
  std::span<const GridPoint> points_;
  std::span<const std::array<uint32_t, 4>> reference_;
  Csr incident_;  // per point, the reference tetrahedra at it, ascending
};

// Every cell's, on every core. `cells` and `reference` name `points` (grid
// ids); every cell must share a vertex with some reference tetrahedron (a
// kept cell of level 0 does).
CellSources cell_sources(std::span<const GridPoint> points,
                         std::span<const std::array<uint32_t, 4>> reference,
                         std::span<const std::array<uint32_t, 4>> cells);

}  // namespace dtm
