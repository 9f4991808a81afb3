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
  bool solid() const { return shape <= Shape::kHexahedron; }
  bool face() const { return shape == Shape::kTriangle || shape == Shape::kQuadrilateral; }
};
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

// A 10-node tetrahedron's edge nodes: Abaqus's slots 4-9, on the edges
// (0,1) (1,2) (0,2) (0,3) (1,3) (2,3) (VTK's order), listed in the order of
// InputMesh::tet_edge_nodes ((0,1) (0,2) (0,3) (1,2) (1,3) (2,3)).
inline constexpr std::array<int, 6> kEdgeSlot = {4, 6, 7, 5, 8, 9};

}  // namespace dtm::abaqus
