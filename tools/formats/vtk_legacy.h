// VTK legacy .vtk files, DATASET UNSTRUCTURED_GRID, ASCII or BINARY (big-endian):
// https://vtk.org/wp-content/uploads/2015/04/file-formats.pdf. Both the
// classic cell layout ("CELLS n size", VTK <= 9.0) and the OFFSETS /
// CONNECTIVITY layout of version 5.1 (VTK >= 9.1) are read.
#pragma once

#include <string>

#include "input_mesh.h"
#include "mesh_writers.h"

namespace dtm {

// Points, VTK_TETRA cells (other cell types are checked and ignored) and the
// POINT_DATA arrays (SCALARS, VECTORS, NORMALS, FIELD). Throws FormatError
// naming the file and the line (the byte offset inside binary data).
InputMesh read_vtk_legacy(const std::string& path);

// Version 4.2 with the classic cell layout, which every VTK and meshio reads:
// float64 points, VTK_TETRA cells, point data `level` (int) and `boundary`
// (unsigned_char) when present.
std::string render_vtk_legacy(const OutputMesh& mesh, bool binary);

}  // namespace dtm
