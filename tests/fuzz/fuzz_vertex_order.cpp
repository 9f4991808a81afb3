// The vertex order section (spec/FORMAT.md §3.9) on arbitrary bytes, below
// the layer checksum that keeps the stream targets from reaching it
// damaged: never a crash; a section that decodes names every vertex once,
// and its order coded again decodes to the same order.
//
// Input: byte 0: which point set (fuzz_point_sets.h, by bit 0); then the
// section, over the Delaunay neighbours of that point set.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/vertex_order_coder.h"
#include "fuzz_check.h"
#include "fuzz_point_sets.h"
#include "mesh/delaunay.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool cloud = data[0] & 1;
  static const dtm::Csr block = dtm::vertex_neighbours(
      fuzz_point_set(false).size(), dtm::delaunay_tetrahedralize(fuzz_point_set(false)).value().cells);
  static const dtm::Csr random = dtm::vertex_neighbours(
      fuzz_point_set(true).size(), dtm::delaunay_tetrahedralize(fuzz_point_set(true)).value().cells);
  const dtm::Csr& neighbours = cloud ? random : block;
  std::vector<uint32_t> order;
  const dtm::Status s = dtm::decode_vertex_order(std::span(data + 1, size - 1), neighbours, order);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(order.size() == neighbours.rows());
  std::vector<uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (uint32_t k = 0; k < sorted.size(); ++k) FUZZ_CHECK(sorted[k] == k);
  std::vector<uint32_t> back;
  FUZZ_CHECK(dtm::decode_vertex_order(dtm::encode_vertex_order(neighbours, order), neighbours, back).ok());
  FUZZ_CHECK(back == order);
  return 0;
}
