// Hexahedra, prisms (wedges) and pyramids read as tetrahedra: the levels
// are tetrahedral meshes, and the input's cells of other shapes are its
// solid all the same (a CFD mesh's boundary layer of prisms, a
// transfinite block of hexahedra). Each cell is split by coning from its
// corner of least index to the faces that do not hold it, each
// quadrilateral face by its diagonal through its own corner of least index
// (Dompierre et al., "How to subdivide pyramids, prisms and hexahedra into
// tetrahedra", 1999): two cells sharing a face split it alike, whatever
// their shapes, so the tetrahedra of a conforming mesh are conforming.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "common/grid.h"
#include "input_mesh.h"

namespace dtm {

// Appends the tetrahedra of the cell whose corners (indices into `points`,
// in gmsh's and VTK's order: a pyramid's base 0-3 and apex 4, a prism's
// triangles 0-2 and 3-5, a hexahedron's quadrilaterals 0-3 and 4-7) are
// `corners`, 5, 6 or 8 of them: 2, 3 or 6 tetrahedra, each positively
// oriented (as gmsh's and VTK's own tetrahedra are: --exact wants one
// orientation throughout), whichever way the cell turns. Any other count
// appends nothing.
void split_cell(std::span<const uint32_t> corners, std::span<const InputPoint> points,
                std::vector<std::array<uint32_t, 4>>& out);

// A quadrilateral (a tagged face of such cells) as the two triangles of
// its diagonal through its corner of least index, as split_cell() splits
// it.
std::array<std::array<uint32_t, 3>, 2> split_quad(const std::array<uint32_t, 4>& q);

// For a reader of cells one at a time: appends the quadrilateral or cell
// whose nodes are `nodes` (corners first, `corners` of them: 4, 5, 6 or 8)
// to `mesh`, a quadrilateral's two triangles to tagged_faces, another
// cell's tetrahedra to tets, and its nodes past its corners (a second-order
// one's) to other_edge_nodes, second_order_cells counting a cell that has
// some (second_order.h). Returns how many triangles or tetrahedra it
// added, each the cell's (its data, its tag).
size_t add_split_cell(std::span<const uint32_t> nodes, size_t corners, InputMesh& mesh);

// What a reader says of the cells it split, by corner count (5, 6, 8): "the
// shapes of its 12 hexahedra, 3 prisms: each is read as the tetrahedra
// that split it (...)", for InputMesh::left_out; empty for none.
std::string split_cells_note(const std::map<size_t, uint64_t>& cells_by_corners);

}  // namespace dtm
