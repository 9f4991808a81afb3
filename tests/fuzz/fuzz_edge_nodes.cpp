// The edge node section (spec/FORMAT.md §3.11) on arbitrary bytes, below the
// layer checksum that keeps the stream targets from reaching it damaged,
// read as 18.0's, 19.0's and 20.0's (each offset from the surface's
// prediction, 20.0's with the creases apart):
// never a crash; a section that decodes gives every edge of the level a
// node or none, each offset within reach and a moved node's nonzero, which
// code again to a section that decodes to the same nodes.
//
// Input: byte 0: which point set (bit 0, fuzz_point_sets.h), which of its
// Delaunay cells the level keeps (bits 1-2: all, every other, two in
// three, one in five) and the grid's bits (bits 3-7: 4 + their value
// modulo 21); then the section, over that level's edges.
#include <array>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "codec/sections/edge_node_coder.h"
#include "fuzz_check.h"
#include "fuzz_level_edges.h"
#include "fuzz_point_sets.h"
#include "mesh/delaunay.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool cloud = data[0] & 1;
  const int pattern = (data[0] >> 1) & 3;
  const int qbits = 4 + (data[0] >> 3) % 21;
  const FuzzLevel level = fuzz_level(cloud, pattern);
  const dtm::TetMesh& mesh = level.mesh;
  const std::vector<uint8_t>& kept = level.kept;
  const dtm::LevelEdges& edges = level.edges;
  // 18.0's offsets, 19.0's differences from the surface's prediction and
  // 20.0's (the creases apart).
  const dtm::EdgeNodePredictor v19(mesh, kept, fuzz_point_set(cloud), qbits, false),
      v20(mesh, kept, fuzz_point_set(cloud), qbits, true);
  for (const dtm::EdgeNodePredictor* p : {static_cast<const dtm::EdgeNodePredictor*>(nullptr), &v19, &v20}) {
    dtm::EdgeNodeOffsets nodes;
    const dtm::Status s = dtm::decode_edge_nodes(std::span(data + 1, size - 1), edges, qbits, nodes, p);
    if (!s.ok()) {
      FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
      continue;
    }
    FUZZ_CHECK(nodes.present.size() == edges.corners.size() && nodes.offset.size() == edges.corners.size());
    for (size_t e = 0; e < edges.corners.size(); ++e)
      for (int64_t d : nodes.offset[e]) {
        FUZZ_CHECK(d > -dtm::edge_node_reach(qbits) && d < dtm::edge_node_reach(qbits));
        FUZZ_CHECK(nodes.present[e] || d == 0);
      }
    dtm::EdgeNodeOffsets again;
    FUZZ_CHECK(
        dtm::decode_edge_nodes(dtm::encode_edge_nodes(edges, nodes, qbits, p), edges, qbits, again, p).ok());
    FUZZ_CHECK(again.present == nodes.present && again.offset == nodes.offset);
  }
  return 0;
}
