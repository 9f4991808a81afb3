// The candidate section written (spec/FORMAT.md §3.4): the encoder's side
// of candidate_coder.h.
#include <algorithm>
#include <bit>
#include <cstdlib>
#include <vector>

#include "codec/sections/candidate_coder.h"
#include "codec/sections/candidate_coder_shared.h"
#include "common/parallel_for.h"
#include "common/parallel_sort.h"

namespace dtm {
namespace {

// The candidates grouped by their place halved on every axis (their Morton
// code over 8: consecutive in the list), an open-addressing table from a
// group's key to its first candidate. A point's neighbourhood of 3 x 3 x 3
// places meets at most 2 x 2 x 2 groups.
class CandidateGroups {
 public:
  explicit CandidateGroups(const CandidateList& candidates)
      : slots_(std::bit_ceil(2 * candidates.size() + 2), UINT32_MAX), candidates_(candidates) {
    for (uint32_t i = 0; i < candidates.size(); ++i) {
      if (i > 0 && candidates.code(i) >> 3 == candidates.code(i - 1) >> 3) continue;
      size_t s = slot(candidates.code(i) >> 3);
      while (slots_[s] != UINT32_MAX) s = (s + 1) & (slots_.size() - 1);
      slots_[s] = i;
    }
  }
  // The first candidate of the group `key`, or UINT32_MAX.
  uint32_t first(uint64_t key) const {
    for (size_t s = slot(key);; s = (s + 1) & (slots_.size() - 1))
      if (slots_[s] == UINT32_MAX || candidates_.code(slots_[s]) >> 3 == key) return slots_[s];
  }

 private:
  size_t slot(uint64_t key) const {
    uint64_t h = key * 0x9E3779B97F4A7C15ull;
    h ^= h >> 29;
    return h & (slots_.size() - 1);
  }
  std::vector<uint32_t> slots_;
  const CandidateList& candidates_;
};

}  // namespace

std::vector<CandidateHit> points_beside(const CandidateList& candidates, std::span<const GridPoint> points) {
  const CandidateGroups groups(candidates);
  const int q = candidates.qbits;
  const int32_t top = (1 << q) - 1;
  // Each point's hits on its own (on every core), then sorted: the hits
  // are the same, in the same order, for any number of threads.
  std::vector<CandidateHit> out = collect_in_order<CandidateHit>(
      points.size(), 16384, [&](size_t first, size_t last, std::vector<CandidateHit>& hits) {
        for (auto p = static_cast<uint32_t>(first); p < last; ++p) {
          const GridPoint& x = points[p];
          // The groups of the places x - 1 .. x + 1 on each axis, clamped to the grid.
          int32_t lo[3], hi[3];
          const int32_t c[3] = {x.x, x.y, x.z};
          for (int a = 0; a < 3; ++a)
            lo[a] = std::max(0, c[a] - 1) >> 1, hi[a] = std::min(top, c[a] + 1) >> 1;
          for (int32_t gx = lo[0]; gx <= hi[0]; ++gx)
            for (int32_t gy = lo[1]; gy <= hi[1]; ++gy)
              for (int32_t gz = lo[2]; gz <= hi[2]; ++gz) {
                const uint64_t key = static_cast<uint64_t>(morton_encode({gx, gy, gz}, q));
                for (uint32_t i = groups.first(key); i < candidates.size() && candidates.code(i) >> 3 == key;
                     ++i) {
                  const GridPoint at = candidates.at(i);
                  const int dx = x.x - at.x, dy = x.y - at.y, dz = x.z - at.z;
                  if (std::abs(dx) > 1 || std::abs(dy) > 1 || std::abs(dz) > 1) continue;
                  hits.push_back({i, static_cast<uint8_t>((dx + 1) + 3 * (dy + 1) + 9 * (dz + 1)), p});
                }
              }
        }
      });
  parallel_sort(out.begin(), out.end());
  return out;
}

std::vector<uint8_t> encode_candidate_section(const CandidateList& candidates,
                                              std::span<const CandidateHit> beside, size_t point_count,
                                              std::vector<uint8_t>& sent) {
  // Each candidate in turn takes its first free point by offset.
  sent.assign(point_count, 0);
  std::vector<int8_t> hit(candidates.size(), -1);
  for (const CandidateHit& b : beside) {
    if (hit[b.candidate] >= 0 || sent[b.point]) continue;
    hit[b.candidate] = static_cast<int8_t>(b.offset);
    sent[b.point] = 1;
  }
  RangeEncoder enc;
  CandidateModels models;
  for (size_t i = 0; i < candidates.size(); ++i) {
    enc.encode(models.flag[candidates.context(i)], hit[i] >= 0);
    if (hit[i] < 0) continue;
    for (int b = kOffsetBits - 1, node = 1; b >= 0; --b) {
      const bool bit = (hit[i] >> b) & 1;
      enc.encode(models.offset[node], bit);
      node = 2 * node + bit;
    }
  }
  return enc.finish();
}

std::vector<uint8_t> encode_candidate_section(const CandidateList& candidates,
                                              std::span<const GridPoint> points, std::vector<uint8_t>& sent) {
  return encode_candidate_section(candidates, points_beside(candidates, points), points.size(), sent);
}

}  // namespace dtm
