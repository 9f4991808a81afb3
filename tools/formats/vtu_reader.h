// VTK XML UnstructuredGrid .vtu files (https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html):
// DataArrays in format="ascii", format="binary" (base64) or format="appended"
// (AppendedData encoding="raw" or "base64"), either byte order, UInt32 or
// UInt64 headers. Compressed files (a `compressor` attribute) are rejected
// as unsupported. The writer is in mesh_writers.cpp.
#pragma once

#include <string>

#include "input_mesh.h"

namespace dtm {

// Points, VTK_TETRA cells (other cell types are checked and ignored) and the
// PointData arrays. One <Piece>. Throws FormatError naming the file and the
// line of the offending element (the byte offset inside raw appended data).
InputMesh read_vtu(const std::string& path);

}  // namespace dtm
