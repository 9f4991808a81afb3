// VTK's cell types, as the .vtk and .vtu readers and writers name them.
#pragma once

#include <string>

namespace dtm {

inline constexpr int kVtkTriangle = 5;
inline constexpr int kVtkTetra = 10;

// A cell type by name, the usual ones (for what a reader leaves out).
inline std::string vtk_cell_name(int type) {
  switch (type) {
    case 1:
      return "vertices";
    case 3:
      return "lines";
    case 5:
      return "triangles";
    case 9:
      return "quads";
    case 12:
      return "hexahedra";
    case 13:
      return "wedges";
    case 14:
      return "pyramids";
    case 24:
      return "quadratic tetrahedra";
    default:
      return "of VTK type " + std::to_string(type);
  }
}

}  // namespace dtm
