// Point sets and surfaces through CGAL's readers (CGAL 5.5 Point_set_3 and
// polygon soup I/O): PLY (ASCII and binary, float or double), OFF, OBJ and
// XYZ. Only the vertices are used; faces are read past. CGAL stays in
// cgal_point_sets.cpp, which is slow to compile.
#pragma once

#include <string>

#include "input_mesh.h"

namespace dtm {

enum class PointSetFormat { kPly, kOff, kObj, kXyz };

// Vertices and, for PLY, every other vertex property as a field ("normal"
// with 3 components for nx ny nz; colours, intensities, ... one each).
// Throws FormatError naming the file: CGAL's readers report neither line nor
// offset, so the message says what the reader needs instead.
InputMesh read_point_set(const std::string& path, PointSetFormat format);

}  // namespace dtm
