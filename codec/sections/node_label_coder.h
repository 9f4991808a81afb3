// The input's node labels (format 22.0, spec/FORMAT.md §3.14; meshenc
// --keep-order of a file whose node ids are not 1 to n), encoder and
// decoder side by side.
//
// The vertex order (§3.9) and node order (§3.13) sections give the nodes
// back in the input's order, numbered 1 to n. A file may name its nodes
// otherwise: gmsh's node tags skip where entities were removed, an Abaqus
// deck numbers each part's nodes from its own offset, an Exodus file maps
// its nodes to global ids. A solver deck or a results file that names node
// 10234 needs node 10234 back, not the node of rank 10234. This section
// gives each node's label in the input's order: mostly the one before it
// plus one (a zero gap, next to nothing), else the gap's sign and size.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "common/status.h"

namespace dtm {

// A label lies in [1, kMaxNodeLabel]: every gap between two fits an int64,
// and gmsh's, Abaqus's and Exodus's ids are positive.
inline constexpr int64_t kMaxNodeLabel = (int64_t{1} << 62) - 1;

// Whether `labels` can be coded: each in [1, kMaxNodeLabel], no two alike.
bool valid_node_labels(std::span<const int64_t> labels);

// `labels`: valid_node_labels().
std::vector<uint8_t> encode_node_labels(std::span<const int64_t> labels);
// kCorrupt unless the section gives `count` labels, each in range and no
// two alike, and ends where its bytes do.
Status decode_node_labels(std::span<const uint8_t> section, size_t count, std::vector<int64_t>& labels);

}  // namespace dtm
