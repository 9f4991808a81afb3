// The candidate section's decoder (spec/FORMAT.md §3.4) on arbitrary bytes,
// below the layer checksum that keeps the stream-level targets from reaching
// it with a damaged section: never a crash; what decodes is at most the
// points allowed, inside the grid; and of a set of distinct new points that
// decodes, the encoder sends back a section that decodes to the points it
// marks as sent (its greedy choice, candidate by candidate, may leave a point
// for the payload that another choice would have sent).
//
// Input: byte 0: which point set is the coarser level (a 4x4x4 block, or 300
// pseudo-random points of a 7-bit grid, by bit 0), which candidates (bits 1-2:
// kinds 1, 2 or 3; 0 reads as 3) and how many points the layer has (bits 3-7,
// times 4, plus 1); then the section.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/candidate_coder.h"
#include "fuzz_check.h"
#include "fuzz_point_sets.h"
#include "mesh/delaunay.h"

namespace {

constexpr int kQBits = 7;

std::vector<dtm::MortonCode> codes_of(std::span<const dtm::GridPoint> points) {
  std::vector<dtm::MortonCode> out;
  for (const dtm::GridPoint& p : points) out.push_back(dtm::morton_encode(p, kQBits));
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool random = data[0] & 1;
  const auto& coarse = fuzz_point_set(random);
  static const dtm::TetMesh block_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(false)).value();
  static const dtm::TetMesh cloud_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(true)).value();
  const dtm::TetMesh& dt = random ? cloud_dt : block_dt;
  const uint8_t kinds = ((data[0] >> 1) & 3) == 0 ? dtm::kKnownCandidateKinds : ((data[0] >> 1) & 3);
  const uint32_t max_points = 4u * (data[0] >> 3) + 1;
  const std::vector<dtm::MortonCode> known = codes_of(coarse);
  const auto candidates = dtm::layer_candidates(dt.cells, coarse, known, kQBits, kinds);
  // The list is the spec's: ascending, distinct, none known, inside the grid.
  for (size_t i = 0; i < candidates.size(); ++i) {
    FUZZ_CHECK(i == 0 || candidates.code(i - 1) < candidates.code(i));
    FUZZ_CHECK(!std::binary_search(known.begin(), known.end(), dtm::MortonCode{candidates.code(i)}));
    FUZZ_CHECK(candidates.context(i) < dtm::kCandidateContexts);
    FUZZ_CHECK(dtm::morton_encode(candidates.at(i), kQBits) == candidates.code(i));
  }
  std::vector<dtm::GridPoint> sent;
  const dtm::Status s = dtm::decode_candidate_section({data + 1, size - 1}, candidates, max_points, sent);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(sent.size() <= max_points);
  for (const dtm::GridPoint& p : sent)
    FUZZ_CHECK(p.x >= 0 && p.y >= 0 && p.z >= 0 && p.x < (1 << kQBits) && p.y < (1 << kQBits) &&
               p.z < (1 << kQBits));
  // The decoder's caller refuses repeats and known points; a set without
  // them goes back through the encoder.
  std::vector<dtm::MortonCode> codes = codes_of(sent);
  if (std::adjacent_find(codes.begin(), codes.end()) != codes.end()) return 0;
  for (dtm::MortonCode c : codes)
    if (std::binary_search(known.begin(), known.end(), c)) return 0;
  std::vector<uint8_t> marked;
  const std::vector<uint8_t> section = dtm::encode_candidate_section(candidates, sent, marked);
  std::vector<dtm::GridPoint> marked_points;
  for (size_t i = 0; i < sent.size(); ++i)
    if (marked[i]) marked_points.push_back(sent[i]);
  std::vector<dtm::GridPoint> again;
  FUZZ_CHECK(dtm::decode_candidate_section(section, candidates, max_points, again).ok());
  FUZZ_CHECK(codes_of(again) == codes_of(marked_points));
  return 0;
}
