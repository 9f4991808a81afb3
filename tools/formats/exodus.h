// Exodus II (.e, .exo, .ex2, .g, .gen): the mesh and results file of
// Sandia's SEACAS tools, Cubit, MOOSE and ParaView, a netCDF file (classic
// or netCDF-4) read and written through Debian's libexodusii.
#pragma once

#include <string>
#include <vector>

#include "input_mesh.h"
#include "mesh_writers.h"

namespace dtm {

// The nodes and, by element block:
// * tetrahedra (TETRA/TET, 4 nodes; 10: their edge nodes kept as a
//   second-order mesh's), hexahedra, wedges and pyramids split into
//   tetrahedra (cell_split.h), each block a region (its id the label, its
//   name the region's);
// * triangles and quadrilaterals (TRI, TRISHELL, SHELL, QUAD in 3D) tagged
//   faces, tagged by their block's id;
// * side sets: the sides of those elements, tagged faces (the set's id the
//   tag, its name the tag's);
// * node sets: a uint8 field "nset:NAME" each (kNodeSetFieldPrefix; the
//   set's id where it has no name: a named set's id that render_exodus()
//   would not give it again is named as left out);
// * the nodal variables at time step `time_step` (1 the first; 0, the
//   last), point fields (X_x, X_y, X_z one 3-component field X), and the
//   element variables defined on every solid block, cell data.
// The rest (other elements, earlier time steps, global and set variables,
// element sets, maps, QA and info records) is named in InputMesh::left_out.
// A 2D mesh is refused. Throws FormatError naming the file.
InputMesh read_exodus(const std::string& path, int time_step = 0);

// The mesh as an Exodus II file (netCDF classic, 64-bit offsets): one
// element block a region (TETRA, or TETRA10 with edge nodes; its label the
// block's id where positive), one side set a face tag, one node set a node
// set field (is_node_set_field()), the other fields nodal variables and the
// cell data element variables at one time step (time 0; a 3-component
// field as X_x, X_y, X_z). Throws std::runtime_error if libexodusii
// fails.
std::string render_exodus(const OutputMesh& mesh);

// The ids render_exodus() gives what `labels` name (blocks, side sets,
// node sets): each label where it is positive and not taken before, the
// others the next free ids from 1.
std::vector<int64_t> exodus_ids(const std::vector<int64_t>& labels);

// Where render_exodus() gives a region or a face tag another id than its
// label (a label of 0 or less: Exodus ids are positive; a region of linear
// and second-order cells: two blocks), one phrase each, for the tool to
// say ("region -4 as element block 3 (Exodus ids are positive)").
std::vector<std::string> exodus_renumbering(const OutputMesh& mesh);

}  // namespace dtm
