// VTK's cell types, as the .vtk and .vtu readers and writers name them.
#pragma once

#include <array>
#include <string>

namespace dtm {

inline constexpr int kVtkTriangle = 5;
inline constexpr int kVtkTetra = 10;
inline constexpr int kVtkQuad = 9;
inline constexpr int kVtkHexahedron = 12;
inline constexpr int kVtkWedge = 13;
inline constexpr int kVtkPyramid = 14;
inline constexpr int kVtkQuadraticTriangle = 22;
// A hexahedron, wedge, pyramid or quadrilateral, linear or of second order
// (its corners first), read as the tetrahedra (triangles) that split it
// (cell_split.h): its nodes and corners; {0, 0} for another type. (A
// double: a .vtu's types array may be of any type, and hold anything.)
struct VtkSplitType {
  size_t nodes = 0, corners = 0;
};
inline VtkSplitType vtk_split_type(double type) {
  constexpr std::array<std::array<int, 3>, 11> kTypes = {{{kVtkHexahedron, 8, 8},
                                                          {25, 20, 8},
                                                          {29, 27, 8},
                                                          {kVtkWedge, 6, 6},
                                                          {26, 15, 6},
                                                          {32, 18, 6},
                                                          {kVtkPyramid, 5, 5},
                                                          {27, 13, 5},
                                                          {kVtkQuad, 4, 4},
                                                          {23, 8, 4},
                                                          {28, 9, 4}}};
  for (const auto& [t, nodes, corners] : kTypes)
    if (type == t) return {static_cast<size_t>(nodes), static_cast<size_t>(corners)};
  return {};
}
inline constexpr int kVtkQuadraticTetra = 24;
// VTK's quadratic tetrahedron numbers its edge nodes 4 (0,1), 5 (1,2),
// 6 (0,2), 7 (0,3), 8 (1,3), 9 (2,3): theirs in kTetEdges' order
// (second_order.h).
inline constexpr std::array<int, 6> kVtkTetEdgeNodes = {4, 6, 7, 5, 8, 9};

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
    case 22:
      return "quadratic triangles";
    case 24:
      return "quadratic tetrahedra";
    default:
      return "of VTK type " + std::to_string(type);
  }
}

}  // namespace dtm
