// The candidate section read (spec/FORMAT.md §3.4): the decoder's side of
// candidate_coder.h.
#include <string>
#include <vector>

#include "codec/sections/candidate_coder.h"
#include "codec/sections/candidate_coder_shared.h"

namespace dtm {

Status decode_candidate_section(std::span<const uint8_t> section, const CandidateList& candidates,
                                uint32_t max_points, std::vector<GridPoint>& out) {
  const auto damaged = [](const std::string& what) { return corrupt("candidates: " + what); };
  RangeDecoder dec(section);
  CandidateModels models;
  uint32_t count = 0;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (!dec.decode(models.flag[candidates.context(i)])) continue;
    int s = 0;
    for (int b = 0, node = 1; b < kOffsetBits; ++b) {
      const bool bit = dec.decode(models.offset[node]);
      node = 2 * node + bit;
      s = 2 * s + bit;
    }
    if (s >= kOffsets) return damaged("an offset out of range");
    if (++count > max_points) return damaged("more points than the layer has");
    const GridPoint c = candidates.at(i);
    const int64_t x = int64_t{c.x} + s % 3 - 1, y = int64_t{c.y} + (s / 3) % 3 - 1,
                  z = int64_t{c.z} + s / 9 - 1;
    if (!candidate_inside_grid(x, y, z, candidates.qbits)) return damaged("a point outside the grid");
    out.push_back({static_cast<int32_t>(x), static_cast<int32_t>(y), static_cast<int32_t>(z)});
    if (dec.overran()) break;
  }
  if (!dec.finished_cleanly()) return damaged("the section does not end where its bytes do");
  return Status::Ok();
}

}  // namespace dtm
