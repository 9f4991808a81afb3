// Abaqus and CalculiX input files (.inp): the mesh of a structural model, as
// gmsh (-format inp), Netgen ("Abaqus Format"), meshio, CalculiX's cgx and
// Abaqus/CAE write it. Keyword lines start with '*' (a '**' line is a
// comment), keywords and their parameters ignore case, data lines are
// comma-separated; *INCLUDE pulls in another file.
#pragma once

#include <string>
#include <vector>

#include "input_mesh.h"
#include "mesh_writers.h"

namespace dtm {

// The nodes (*NODE, in file order), the solid elements (C3D4 and C3D10
// variants as tetrahedra, their edge nodes set aside as a second-order
// mesh's; C3D5, C3D6, C3D8 and their second-order variants split into
// tetrahedra, cell_split.h) and:
// * regions: the *SOLID SECTION element sets, named by them; without
//   sections, the element sets that partition the solid elements (*ELSET
//   first, then the *ELEMENT lines' ELSET=; a set of them all is not one);
// * tagged faces: the element-based *SURFACE faces (S1..S6) and the 2D
//   elements' triangles and quadrilaterals, tagged by surface or set;
// * each node set (*NSET, *NODE NSET=) a uint8 field "nset:NAME", 1 on its
//   nodes, which render_abaqus() writes back as the set (the first 32).
// Sets that a *SURFACE names, that Abaqus/CAE marks INTERNAL, or of an
// *ASSEMBLY are no regions. One *PART is read as the model, with its one
// *INSTANCE unmoved (the assembly's reference points named); several
// parts or instances, a moved instance, *NGEN and the other keywords that
// make or move nodes, and *NODE, SYSTEM= other than R are refused. What
// else the file holds (other elements and sets, materials, steps) is named
// in InputMesh::left_out. Throws FormatError naming the file, and the line
// where one line is at fault.
InputMesh read_abaqus(const std::string& path);

// The prefix of a node set's field (read_abaqus, render_abaqus).
inline constexpr const char* kNodeSetFieldPrefix = "nset:";

// An input file of the mesh: *NODE (numbered 1..n), *ELEMENT blocks of C3D4
// and of C3D10 (cells with edge nodes), numbered in the mesh's order, an
// *ELSET a region (named by the region table, or
// REGION_<label>), an element-based *SURFACE a face tag (FACES_<tag>
// without a name), and an *NSET a node set field (kNodeSetFieldPrefix, 0/1
// values). The other fields and the cell data have no place in it
// (not_written()).
std::string render_abaqus(const OutputMesh& mesh);
// What render_abaqus() writes under another name than the stream's: a name
// made an Abaqus label (letters, digits, '_' and '-', from a letter, 72
// characters), or told apart from another of its kind ("_2"), for
// meshdec's "written as" lines.
std::vector<std::string> abaqus_renaming(const OutputMesh& mesh);

// A field render_abaqus() writes as a node set: one uint8 (or int8)
// component, named kNodeSetFieldPrefix + the set's name.
bool is_node_set_field(const OutputField& f);

}  // namespace dtm
