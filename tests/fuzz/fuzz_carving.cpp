// The carving section's decoder (spec/FORMAT.md §3.2) on arbitrary bytes,
// below the layer checksum that keeps the stream-level targets from reaching
// it with a damaged section: never a crash, and whatever decodes is one
// verdict per cell, which re-encodes to the same section.
//
// Input: byte 0: which point set (a 4x4x4 block, or 300 pseudo-random
// points of a 7-bit grid, by bit 0), which contexts (6.0's by bit 1, and
// with bit 7 an exact level 0's, 12.0's by bit 2, else 11.0's; else 4.0's)
// and alpha (bits 2-6, in quarter grid steps); then the section.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/carving_coder.h"
#include "fuzz_check.h"
#include "fuzz_point_sets.h"
#include "mesh/delaunay.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const auto& points = fuzz_point_set(data[0] & 1);
  static const dtm::TetMesh block_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(false)).value();
  static const dtm::TetMesh cloud_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(true)).value();
  const dtm::TetMesh& dt = (data[0] & 1) ? cloud_dt : block_dt;
  // Bit 1: 6.0's contexts (with bit 7 too: an exact level 0's, split by
  // the margin, by the shape too with bit 2: 12.0's, and by the flip too
  // with bits 2 and 3: 13.0's); bits 2-6: alpha.
  const dtm::CarvingContexts contexts =
      !(data[0] & 2)    ? dtm::CarvingContexts::kAlphaNeighbours
      : (data[0] & 128) ? ((data[0] & 12) == 12 ? dtm::CarvingContexts::kExactMarginShapeFlip
                           : (data[0] & 4)      ? dtm::CarvingContexts::kExactMarginShape
                                                : dtm::CarvingContexts::kExactMargin)
                        : dtm::CarvingContexts::kDecodedNeighbours;
  const double alpha = 0.25 * ((data[0] >> 2) & 31) + 0.25;
  const std::span<const uint8_t> section(data + 1, size - 1);
  std::vector<uint8_t> kept;
  const dtm::Status s = dtm::decode_carving(section, dt, points, alpha, contexts, kept);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(kept.size() == dt.cells.size());
  const std::vector<uint8_t> again = dtm::encode_carving(dt, points, alpha, kept, contexts);
  // A section that decodes is the encoder's, or empty where no bit is set.
  FUZZ_CHECK(std::vector<uint8_t>(section.begin(), section.end()) == again || again.empty());
  return 0;
}
