// Second-order meshes (gmsh -order 2, VTK's quadratic cells, Netgen's
// SecondOrder()) read as their linear cells: the nodes on the elements'
// edges are not vertices of any level, so they are set aside before the
// tools see the points.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "input_mesh.h"

namespace dtm {

// Corners (a, b) of a tetrahedron's six edges, in the order of
// InputMesh::tet_edge_nodes.
inline constexpr std::array<std::array<int, 2>, 6> kTetEdges = {
    {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

// A linear tetrahedron's entry of InputMesh::tet_edge_nodes.
inline constexpr std::array<uint32_t, 6> kNoEdgeNodes = {InputMesh::kNoEdgeNode, InputMesh::kNoEdgeNode,
                                                         InputMesh::kNoEdgeNode, InputMesh::kNoEdgeNode,
                                                         InputMesh::kNoEdgeNode, InputMesh::kNoEdgeNode};

// For readers that add tetrahedra one at a time: the edge nodes (in
// kTetEdges' order) of the one just added, the linear ones before it given
// none. set_edge_nodes_aside() gives none to the linear ones after the last.
void add_tet_edge_nodes(InputMesh& mesh, const std::array<uint32_t, 6>& nodes);

// Per point of `mesh` as a reader leaves it: kNodeCorner where it is a
// tetrahedron's or tagged face's corner, | kNodeOnEdge where it is a
// second-order element's edge node (tet_edge_nodes, other_edge_nodes).
inline constexpr uint8_t kNodeCorner = 1, kNodeOnEdge = 2;
std::vector<uint8_t> node_roles(const InputMesh& mesh);

// Moves the points that the readers found on second-order elements' edges
// and that are no element's corner from mesh.points to mesh.edge_points (in
// file order), renumbering the tetrahedra, the tagged faces and the
// per-vertex fields (whose values at those nodes go to their edge_values) and making
// tet_edge_nodes index edge_points (kNoEdgeNode where a node is some
// element's corner). Names what that leaves out in mesh.left_out. Does
// nothing to a linear mesh, and to one without tetrahedra but forgets its
// edge nodes (a surface's points are all kept: its cells are not).
void set_edge_nodes_aside(InputMesh& mesh);

// What set_edge_nodes_aside() says it leaves out (its left_out entry,
// which starts "N nodes on the edges of second-order elements"), or,
// when the tetrahedra's edge nodes are kept (meshenc --exact: format
// 18.0, with the fields' values there: 19.0), what still is: the other
// elements' nodes and, `with_fields`, the fields' values at them; empty for
// nothing.
std::string edge_nodes_note(const InputMesh& mesh, bool tetrahedra_nodes_kept, bool with_fields);

}  // namespace dtm
