// Incidence structures derived from a TetMesh: who touches whom, as
// compressed sparse rows built in linear time.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/csr.h"
#include "mesh/delaunay.h"

namespace dtm {

// For each vertex, the cells incident to it (ascending cell index).
Csr vertex_cells(std::span<const std::array<uint32_t, 4>> cells, size_t num_vertices);
inline Csr vertex_cells(const TetMesh& mesh, size_t num_vertices) {
  return vertex_cells(mesh.cells, num_vertices);
}

// Sorted neighbour lists of the edge graph of `cells`; `cells_of_vertex` is
// vertex_cells(cells, n).
Csr vertex_neighbors(std::span<const std::array<uint32_t, 4>> cells, const Csr& cells_of_vertex);
inline Csr vertex_neighbors(const TetMesh& mesh, const Csr& cells_of_vertex) {
  return vertex_neighbors(mesh.cells, cells_of_vertex);
}

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

// The canonical order of cells: by their vertex ids sorted ascending,
// compared lexicographically (a triangulation has no two cells on the same
// four vertices). order[k] is the cell at place k. Linear time: a counting
// sort by smallest vertex, then each vertex's few cells sorted, on every
// core; the identity, at the cost of one pass, when the cells are in it
// already (every exported triangulation's are: mesh/delaunay.h).
std::vector<uint32_t> canonical_cell_order(std::span<const std::array<uint32_t, 4>> cells);

// The faces that belong to exactly one of `cells` (positively oriented
// tetrahedra, any list, not only a Delaunay tetrahedralization's), each
// ordered so that its right-hand normal points away from its cell, in a
// canonical order (sorted by their vertices). Indices are the cells' own.
// The faces are matched in passes over ranges of vertices, each holding at
// most `faces_per_pass` faces (0: an eighth of them, at least 2^24), which
// bounds the memory it takes; the result is the same for any.
std::vector<std::array<uint32_t, 3>> boundary_triangles(std::span<const std::array<uint32_t, 4>> cells,
                                                        size_t faces_per_pass = 0);
// Puts oriented faces in boundary_triangles()' canonical order (ascending by
// their sorted vertices): faces found in parts, gathered, in the whole's.
void sort_as_boundary_triangles(std::vector<std::array<uint32_t, 3>>& faces);

}  // namespace dtm
