// What the Abaqus reader and writer share of the .inp syntax: keyword lines,
// data lines' entries, the element types the mesh is made of and the faces
// S1..S6 of the solids (Abaqus Analysis User's Guide, "Three-dimensional
// solid element library").
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace dtm::abaqus {

std::string upper(std::string_view s);
std::string_view trimmed(std::string_view s);

// A data line's entries: split at commas, each trimmed and unquoted; a
// trailing comma (a line continued, or gmsh's set lists) adds none.
std::vector<std::string_view> entries(std::string_view line);

// A keyword line ("*Element, type=C3D4, ELSET=Volume1"): the keyword and its
// parameters' names in upper case without blanks (*SOLID SECTION is
// *SOLIDSECTION, as Abaqus and CalculiX read them), the values as written
// (unquoted).
struct Keyword {
  std::string name;     // upper case, without blanks
  std::string written;  // upper case, as written
  std::vector<std::pair<std::string, std::string>> parameters;
  bool has(std::string_view p) const;
  std::string value(std::string_view p) const;  // "" when absent
};
Keyword keyword_of(std::string_view line);

// What an element type is to the mesh: its shape, nodes and corners.
enum class Shape : uint8_t { kTetrahedron, kPyramid, kPrism, kHexahedron, kTriangle, kQuadrilateral, kOther };
struct ElementType {
  Shape shape = Shape::kOther;
  int nodes = 0, corners = 0;
};
inline bool is_solid(Shape s) { return s <= Shape::kHexahedron; }
inline bool is_face(Shape s) { return s == Shape::kTriangle || s == Shape::kQuadrilateral; }
// By name (upper case): the solids C3D<n> (and heat transfer's DC3D<n>),
// whatever letters follow (C3D10M, C3D8R, C3D4H); the 2D elements whose
// corners can tag a face (shells S, STRI, membranes M3D, SFM3D, rigid R3D,
// continuum CPS and CPE, heat transfer DS) with 3, 4, 6, 8 or 9 nodes.
ElementType element_type(const std::string& type);

// A solid's face S1..S6 as corner slots (0-based): 3 or 4 of them, none
// where the shape has no such face.
struct FaceSlots {
  int count = 0;
  std::array<int, 4> slots{};
};
FaceSlots face_slots(Shape shape, int face);

// (A C3D10's edge nodes are in VTK's order: kVtkTetEdgeNodes, vtk_cells.h.)

}  // namespace dtm::abaqus
