#include "second_order.h"

#include <algorithm>
#include <string>
#include <vector>

#include "common/release.h"

namespace dtm {

void add_tet_edge_nodes(InputMesh& mesh, const std::array<uint32_t, 6>& nodes) {
  mesh.tet_edge_nodes.resize(mesh.tets.size() - 1, kNoEdgeNodes);
  mesh.tet_edge_nodes.push_back(nodes);
}

std::vector<uint8_t> node_roles(const InputMesh& mesh) {
  std::vector<uint8_t> role(mesh.points.size(), 0);
  for (const auto& t : mesh.tets)
    for (uint32_t v : t) role[v] |= kNodeCorner;
  for (const auto& f : mesh.tagged_faces)
    for (uint32_t v : f) role[v] |= kNodeCorner;
  for (const auto& e : mesh.tet_edge_nodes)
    for (uint32_t v : e)
      if (v != InputMesh::kNoEdgeNode) role[v] |= kNodeOnEdge;
  for (uint32_t v : mesh.other_edge_nodes) role[v] |= kNodeOnEdge;
  return role;
}

void set_edge_nodes_aside(InputMesh& mesh) {
  if (mesh.tet_edge_nodes.empty() && mesh.other_edge_nodes.empty()) return;
  if (mesh.tets.empty()) {
    // A surface mesh: no cell of it is kept (its triangles are not tagged
    // faces of a volume), so its points are all the stream has of it.
    mesh.tet_edge_nodes.clear();
    mesh.other_edge_nodes.clear();
    return;
  }
  if (!mesh.tet_edge_nodes.empty()) mesh.tet_edge_nodes.resize(mesh.tets.size(), kNoEdgeNodes);
  const size_t n = mesh.points.size();
  constexpr uint8_t kOnEdge = kNodeOnEdge;
  const std::vector<uint8_t> role = node_roles(mesh);
  // New indices: the kept points' among the kept, the set-aside nodes'
  // among them.
  std::vector<uint32_t> index(n);
  std::vector<InputPoint> kept;
  kept.reserve(n);
  mesh.node_is_edge_point.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    if (role[i] == kOnEdge) {
      mesh.node_is_edge_point[i] = 1;
      index[i] = static_cast<uint32_t>(mesh.edge_points.size());
      mesh.edge_points.push_back(mesh.points[i]);
    } else {
      index[i] = static_cast<uint32_t>(kept.size());
      kept.push_back(mesh.points[i]);
    }
  }
  const size_t aside = mesh.edge_points.size();
  for (auto& t : mesh.tets)
    for (uint32_t& v : t) v = index[v];
  for (auto& f : mesh.tagged_faces)
    for (uint32_t& v : f) v = index[v];
  for (auto& e : mesh.tet_edge_nodes)
    for (uint32_t& v : e)
      if (v != InputMesh::kNoEdgeNode) v = role[v] == kOnEdge ? index[v] : InputMesh::kNoEdgeNode;
  for (VertexField& f : mesh.fields) {
    const size_t c = static_cast<size_t>(f.components);
    std::vector<double> values;
    values.reserve(c * kept.size());
    f.edge_values.reserve(c * (n - kept.size()));
    for (size_t i = 0; i < n; ++i) {
      std::vector<double>& to = role[i] == kOnEdge ? f.edge_values : values;
      to.insert(to.end(), f.values.begin() + c * i, f.values.begin() + c * (i + 1));
    }
    f.values = std::move(values);
    if (f.at_corners_only) release(f.edge_values);
  }
  mesh.points = std::move(kept);
  mesh.other_edge_nodes.clear();
  mesh.other_edge_nodes.shrink_to_fit();
  if (aside == 0) {
    release(mesh.node_is_edge_point);
    return;
  }
  mesh.left_out.push_back(edge_nodes_note(mesh, false, !mesh.fields.empty()));
}

std::string edge_nodes_note(const InputMesh& mesh, bool tetrahedra_nodes_kept, bool with_fields) {
  uint64_t second_order_tets = 0;
  std::vector<uint8_t> on_tetrahedra(mesh.edge_points.size(), 0);
  for (const auto& e : mesh.tet_edge_nodes) {
    second_order_tets += e[0] != InputMesh::kNoEdgeNode;
    for (uint32_t v : e)
      if (v != InputMesh::kNoEdgeNode) on_tetrahedra[v] = 1;
  }
  const auto kept = static_cast<uint64_t>(std::count(on_tetrahedra.begin(), on_tetrahedra.end(), 1));
  std::string elements;
  if (second_order_tets > 0) elements = std::to_string(second_order_tets) + " second-order tetrahedra";
  if (mesh.second_order_cells > 0)
    elements += (elements.empty() ? "" : ", ") + std::to_string(mesh.second_order_cells) +
                " second-order hexahedra, prisms and pyramids";
  if (!tetrahedra_nodes_kept) {
    std::string what = std::to_string(mesh.edge_points.size()) +
                       " nodes on the edges of second-order elements (" +
                       (elements.empty() ? std::string("faces") : elements) +
                       "): the stream holds the linear cells through their corners";
    if (with_fields) what += ", and the fields' values at their corners only";
    return what;
  }
  // (--exact: the tetrahedra's edge nodes are level 0's, with the fields'
  // values there; the others are not.)
  std::string what;
  if (mesh.edge_points.size() > kept)
    what =
        std::to_string(mesh.edge_points.size() - kept) +
        " nodes of second-order hexahedra, prisms, pyramids and faces that are no tetrahedron's edge nodes";
  if (with_fields && mesh.edge_points.size() > kept) what += ", and the fields' values there";
  return what;
}

}  // namespace dtm
