// gmsh .msh files, ASCII, versions 2.2 and 4.1 (https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format).
// Node tags may be sparse and in any order; binary files are rejected as
// unsupported. Sections other than $Nodes, $Elements and $NodeData are
// read past.
#pragma once

#include <string>

#include "input_mesh.h"
#include "mesh_writers.h"

namespace dtm {

// Points (in the order of the file), 4-node tetrahedra (element type 4;
// other types are checked and ignored) and $NodeData fields that cover every
// node. Throws FormatError naming the file and the line.
InputMesh read_gmsh(const std::string& path);

// Version 4.1 ASCII: one volume entity, nodes tagged 1..n, tetrahedra,
// $NodeData "level" and "boundary" when present.
std::string render_gmsh(const OutputMesh& mesh);

}  // namespace dtm
