// The input's own tetrahedra (TetGen .ele, Medit, VTK, gmsh) as the reference
// shape of every level: how far a level's boundary surface strays from the
// boundary of the mesh the user gave us, both ways. A measurement for the
// report; the hierarchy does not use it.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"
#include "core/quantize.h"
#include "core/surface_distance.h"

namespace dtm {

class ReferenceShape {
 public:
  // `tets` index the input points; `q` maps them onto the grid. Tetrahedra
  // that quantization collapsed are dropped.
  ReferenceShape(std::span<const std::array<uint32_t, 4>> tets, const QuantizedPoints& q);

  size_t tetrahedra() const { return tets_.size(); }
  // The input's tetrahedra on the grid (grid-point indices).
  std::span<const std::array<uint32_t, 4>> tets() const { return tets_; }
  size_t boundary_vertices() const { return boundary_vertices_.size(); }

  // The distance, grid units, between the boundary surface of `cells`
  // (indices into `points`, the grid points `q` held) and the reference's,
  // both ways: from the reference's boundary vertices to the level's
  // surface, and from the level's surface (its vertices and its triangles'
  // centroids, rounded to the grid) to the reference's; and both together
  // (the larger max, the mean over all the points measured). Meant to be
  // called level after level of one hierarchy: what a level shares with the
  // one measured before it is not measured again.
  struct TwoWay {
    DistanceSummary to_level, to_reference, both;
  };
  TwoWay distance(std::span<const std::array<uint32_t, 4>> cells, std::span<const GridPoint> points);

 private:
  std::vector<std::array<uint32_t, 4>> tets_;
  std::vector<std::array<uint32_t, 3>> boundary_;
  std::vector<GridPoint> boundary_vertices_;
  FixedSurface reference_surface_;
  SurfaceDistanceTracker to_level_;  // from boundary_vertices_
  // Squared distance of each grid point to the reference surface, once
  // measured (NaN before): a level's boundary vertices are mostly the
  // previous level's.
  std::vector<double> to_reference_;
};

}  // namespace dtm
