// VTK XML UnstructuredGrid .vtu files (https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html):
// DataArrays in format="ascii", format="binary" (base64) or format="appended"
// (AppendedData encoding="raw" or "base64"), either byte order, UInt32 or
// UInt64 headers, compressed or not (zlib, LZ4 or LZMA blocks, as VTK,
// ParaView and meshio write them by default: vtk_compression.h). The writer
// is in mesh_writers.cpp.
#pragma once

#include <string>

#include "input_mesh.h"

namespace dtm {

// Points, VTK_TETRA cells, the PointData arrays and the CellData arrays
// (InputMesh::tet_arrays, cell_fields), of every <Piece> (one mesh: the
// pieces' points one after the other); VTK_TRIANGLE cells as candidate
// tagged faces. Other cell types (checked) are named in
// InputMesh::left_out. Throws FormatError naming the file and the line of
// the offending element (the byte offset inside raw appended data).
InputMesh read_vtu(const std::string& path);

// A parallel unstructured grid (.pvtu, as ParaView's and VTK's parallel
// writers and meshdec write one): its pieces (.vtu files, paths relative to
// it) read as read_vtu reads them and put together as one mesh; every
// piece must hold the same arrays.
InputMesh read_pvtu(const std::string& path);

}  // namespace dtm
