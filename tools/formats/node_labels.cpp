#include "node_labels.h"

#include <string>

#include "codec/sections/node_label_coder.h"

namespace dtm {

void set_node_labels(InputMesh& mesh, std::vector<int64_t> ids) {
  bool identity = true;
  for (size_t i = 0; i < ids.size() && identity; ++i) identity = ids[i] == static_cast<int64_t>(i + 1);
  if (identity) return;
  if (!valid_node_labels(ids)) {
    mesh.left_out.push_back(
        "the node ids (not all from 1 to 2^62 - 1 and each once, as a stream holds them: the mesh is "
        "numbered "
        "1..n)");
    return;
  }
  mesh.node_labels = std::move(ids);
  mesh.left_out.emplace_back(kNodeIdsNote);
}

void set_node_labels(InputMesh& mesh, const std::unordered_map<int64_t, uint32_t>& index_of) {
  std::vector<int64_t> ids(mesh.points.size(), 0);
  for (const auto& [id, index] : index_of)
    if (index < ids.size()) ids[index] = id;
  set_node_labels(mesh, std::move(ids));
}

}  // namespace dtm
