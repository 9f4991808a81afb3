// The file's own node ids (gmsh's node tags, Abaqus's node numbers, an
// Exodus node map), kept as InputMesh::node_labels where they are not 1 to
// n in the file's order: meshenc --keep-order then keeps them in the
// stream (format 22.0, codec/sections/node_label_coder.h), and without it
// says they are left out.
#pragma once

#include <cstdint>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "input_mesh.h"

namespace dtm {

// What a reader says is left out when it keeps node labels; meshenc takes
// it back where it keeps them.
inline constexpr std::string_view kNodeIdsNote =
    "the node ids (the file numbers its nodes otherwise than 1 to n in order; --keep-order keeps them)";

// `ids`: per point of `mesh` (in the file's order), its id. Sets
// mesh.node_labels and says what is left out, unless the ids are 1 to n in
// order; ids a stream cannot hold (not positive, above 2^62 - 1) are named
// as left out for good.
void set_node_labels(InputMesh& mesh, std::vector<int64_t> ids);
// The same from an id -> point index map that names every point once.
void set_node_labels(InputMesh& mesh, const std::unordered_map<int64_t, uint32_t>& index_of);

}  // namespace dtm
