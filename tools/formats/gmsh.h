// gmsh .msh files, versions 2.0 (as Netgen writes them), 2.2 and 4.1, ASCII
// or binary (little-endian, as gmsh and meshio write it;
// https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format). Node tags may
// be sparse and in any order. Sections other than $Nodes, $Elements and
// $NodeData are read past; what they hold of the mesh (other elements,
// physical tags and names, element data) is named in InputMesh::left_out.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "input_mesh.h"
#include "mesh_writers.h"

namespace dtm {

// Points (in the order of the file), tetrahedra (element type 4, and 11,
// the 10-node ones, as their corners with their edge nodes in
// InputMesh::tet_edge_nodes; hexahedra, prisms and pyramids, types 5 to 7,
// as the tetrahedra that split them, cell_split.h, and their second-order
// types as those, their other nodes in InputMesh::other_edge_nodes; other
// types are checked and ignored), their regions and cell data, tagged triangles (types 2 and
// 9, and quadrangles, 3, as two triangles) and $NodeData fields that cover
// every node, or every node but the second-order elements' edge nodes
// (VertexField::at_corners_only). Throws FormatError naming the file and
// the line.
InputMesh read_gmsh(const std::string& path);

// Version 4.1 ASCII: one volume entity, nodes tagged 1..n, tetrahedra,
// $NodeData "level" and "boundary" when present.
std::string render_gmsh(const OutputMesh& mesh);

// What render_gmsh() writes under another number than the mesh's: a
// region or face tag 0 (gmsh's physical tag 0 is no group, which gmsh
// renumbers) as the tag above the others', one line each.
std::vector<std::string> gmsh_renumbering(const OutputMesh& mesh);

}  // namespace dtm
