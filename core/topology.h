// Incidence structures derived from a TetMesh: who touches whom. Built in
// linear time with counting passes (compressed sparse rows), no hashing.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "delaunay.h"

namespace dtm {

// Rows of variable length stored back to back: row r is
// items[offsets[r] .. offsets[r+1]).
struct Csr {
  std::vector<uint32_t> offsets;
  std::vector<uint32_t> items;
  std::span<const uint32_t> row(size_t r) const {
    return {items.data() + offsets[r], items.data() + offsets[r + 1]};
  }
  size_t rows() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

// For each vertex, the cells incident to it (ascending cell index).
Csr vertex_cells(const TetMesh& mesh, size_t num_vertices);

// Sorted neighbour lists of the edge graph of `mesh`; `cells_of_vertex` is
// vertex_cells(mesh, n).
Csr vertex_neighbors(const TetMesh& mesh, const Csr& cells_of_vertex);

// A face of a carved mesh: cell and the local index of the opposite vertex.
struct BoundaryFace {
  uint32_t cell;
  uint8_t opposite;
};

// The faces of the cells flagged in `in_mesh` whose other side is outside the
// convex hull or a cell not flagged: the topological boundary of the carved mesh.
std::vector<BoundaryFace> boundary_faces(const TetMesh& mesh, std::span<const uint8_t> in_mesh);

// The vertices on the boundary of the carved mesh: on a boundary face, or in
// no flagged cell at all.
std::vector<uint8_t> boundary_vertices(const TetMesh& mesh, size_t num_vertices,
                                       std::span<const uint8_t> in_mesh);

// The triangle of a boundary face, ordered so that its normal points out of
// its cell (right-hand rule).
std::array<uint32_t, 3> outward_triangle(const TetMesh& mesh, std::span<const GridPoint> points,
                                         const BoundaryFace& f);

}  // namespace dtm
