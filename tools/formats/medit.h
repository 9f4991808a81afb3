// Medit .mesh files, ASCII (the INRIA/Gamma format of mmg, TetGen -g, CGAL's
// Mesh_3): keyword sections "Vertices n" (x y z ref), "Tetrahedra n"
// (4 vertex indices, 1-based, and a ref), and others we read past.
// https://www.ljll.fr/frey/publications/RT-0253.pdf
#pragma once

#include <string>

#include "input_mesh.h"
#include "mesh_writers.h"

namespace dtm {

// Points, tetrahedra and the vertex refs (field "ref"). Throws FormatError
// naming the file and line.
InputMesh read_medit(const std::string& path);

// Version 2 (double precision), the boundary flag as the vertex ref (0 when
// absent), tetrahedra with ref 1.
std::string render_medit(const OutputMesh& mesh);

}  // namespace dtm
