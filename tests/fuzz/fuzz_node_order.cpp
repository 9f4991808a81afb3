// The node order section (spec/FORMAT.md §3.13) on arbitrary bytes, below
// the layer checksum that keeps the stream targets from reaching it
// damaged: never a crash; a section that decodes names every vertex, in
// order, and every present node once, and its numbering coded again
// decodes to the same numbering.
//
// Input: byte 0: which point set (bit 0, fuzz_point_sets.h), which of its
// Delaunay cells the level keeps (bits 1-2: all, every other, two in
// three, one in five) and which of their edges have a node (bits 3-4:
// all, every other, one in three, none); then the section, over that
// level's vertices and nodes.
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/node_order_coder.h"
#include "fuzz_check.h"
#include "fuzz_level_edges.h"
#include "fuzz_point_sets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool cloud = data[0] & 1;
  const FuzzLevel level = fuzz_level(cloud, (data[0] >> 1) & 3);
  const int nodes_pattern = (data[0] >> 3) & 3;
  std::vector<uint8_t> present(level.edges.corners.size());
  for (size_t e = 0; e < present.size(); ++e)
    present[e] = nodes_pattern == 0   ? 1
                 : nodes_pattern == 1 ? e % 2 == 0
                 : nodes_pattern == 2 ? e % 3 == 0
                                      : 0;
  const dtm::NodeOrderFrame frame = dtm::node_order_frame(level.edges, present);
  const size_t vertices = fuzz_point_set(cloud).size();
  std::vector<uint32_t> numbering;
  const dtm::Status s =
      dtm::decode_node_order(std::span(data + 1, size - 1), level.edges, frame, vertices, numbering);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  const size_t nodes = frame.edge_of.size();
  FUZZ_CHECK(numbering.size() == vertices + nodes);
  uint32_t next_vertex = 0;
  std::vector<uint8_t> named(nodes, 0);
  for (uint32_t entry : numbering) {
    if (entry < vertices) {
      FUZZ_CHECK(entry == next_vertex++);
    } else {
      FUZZ_CHECK(entry - vertices < nodes && named[entry - vertices]++ == 0);
    }
  }
  std::vector<uint32_t> back;
  FUZZ_CHECK(dtm::decode_node_order(dtm::encode_node_order(level.edges, frame, vertices, numbering),
                                    level.edges, frame, vertices, back)
                 .ok());
  FUZZ_CHECK(back == numbering);
  return 0;
}
