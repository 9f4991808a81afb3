// The carving rule, written once for encoder and decoder (spec/HIERARCHY.md
// §2): a level's mesh keeps the cells of its Delaunay tetrahedralization
// whose circumradius is at most the level's alpha. The circumradius is
// computed on the cell's corners in lexicographic order, so that it is the
// same function of the four points whatever order a triangulation lists them
// in: an encoder and a decoder that build the same cells differently carve
// them identically, bit for bit.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"
#include "mesh/delaunay.h"

namespace dtm {

// How the encoder chose alpha (the stream header records it; spec/FORMAT.md §2).
enum class AlphaKind : uint8_t {
  kPaper = 0,       // mean length of the finite edges of DT(V_l) (eq. 2.1)
  kFixed = 1,       // one value for every level
  kConvexHull = 2,  // keep every cell: alpha = +infinity
};
const char* to_string(AlphaKind kind);

// The circumradius the rule compares with alpha; +infinity for a flat cell.
double carving_radius(std::span<const GridPoint> points, const std::array<uint32_t, 4>& cell);

// True if the cell belongs to the mesh carved with `alpha`.
inline bool kept_by_alpha(std::span<const GridPoint> points, const std::array<uint32_t, 4>& cell,
                          double alpha) {
  return carving_radius(points, cell) <= alpha;
}

// Per cell of `dt`: 1 if kept by the rule.
std::vector<uint8_t> carve(const TetMesh& dt, std::span<const GridPoint> points, double alpha);

}  // namespace dtm
