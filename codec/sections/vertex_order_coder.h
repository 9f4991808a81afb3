// Level 0's vertices in the input's numbering (format 10.0, spec/FORMAT.md
// §3.9; meshenc --keep-order), encoder and decoder side by side. The
// decoder numbers a level's vertices as the layers give them (coarsest
// layer first, Morton order within a layer); a user whose other files name
// the input's node ids needs them back in the input's order. The section
// gives, for each input vertex in turn, which decoded vertex it is: often a
// Delaunay neighbour of the one before (a mesher numbers nodes as it makes
// them, near each other), coded as its index among that vertex's unvisited
// neighbours, else its rank among every vertex not yet named. A random
// numbering costs about log2(n) - 1.44 bits a vertex, a spatially coherent
// one far less.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/csr.h"
#include "common/status.h"

namespace dtm {

// Each vertex's Delaunay neighbours, ascending: the edges of `cells` (all of
// DT(V_0)'s, as the decoder builds them) over `vertices` vertices.
Csr vertex_neighbours(size_t vertices, std::span<const std::array<uint32_t, 4>> cells);

// `order[k]`: the decoded vertex that is input vertex k, a permutation of
// [0, order.size()).
std::vector<uint8_t> encode_vertex_order(const Csr& neighbours, std::span<const uint32_t> order);
// kCorrupt unless the section names every vertex exactly once and ends
// where its bytes do. `order` gets neighbours.rows() entries.
Status decode_vertex_order(std::span<const uint8_t> section, const Csr& neighbours,
                           std::vector<uint32_t>& order);

}  // namespace dtm
