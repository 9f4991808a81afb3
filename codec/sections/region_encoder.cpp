// The region table and sections written (spec/FORMAT.md §2.2, §3.6): the
// encoder's side of region_coder.h.
#include <string>
#include <vector>

#include "codec/sections/region_coder.h"
#include "codec/sections/region_coder_shared.h"
#include "common/byte_io.h"
#include "common/checksum.h"

namespace dtm {

Status check_region_table(std::span<const RegionLabel> regions) {
  if (regions.empty() || regions.size() > kMaxRegionCount)
    return invalid_input("the input has " + std::to_string(regions.size()) +
                         " regions; a stream holds 1 to " + std::to_string(kMaxRegionCount));
  for (size_t i = 0; i < regions.size(); ++i) {
    if (regions[i].name.size() > kMaxRegionNameBytes)
      return invalid_input("region " + std::to_string(regions[i].label) + "'s name has more than " +
                           std::to_string(kMaxRegionNameBytes) + " bytes");
    for (size_t j = 0; j < i; ++j)
      if (regions[j].label == regions[i].label)
        return invalid_input("two regions are labelled " + std::to_string(regions[i].label));
  }
  return Status::Ok();
}

std::vector<uint8_t> write_region_table(std::span<const RegionLabel> regions) {
  ByteWriter body;
  body.u8(static_cast<uint8_t>(regions.size()));
  for (const RegionLabel& r : regions) {
    body.u32(static_cast<uint32_t>(r.label));
    body.u8(static_cast<uint8_t>(r.name.size()));
    for (char ch : r.name) body.u8(static_cast<uint8_t>(ch));
  }
  ByteWriter w;
  w.u32(static_cast<uint32_t>(body.data().size()));
  w.bytes(body.data());
  w.u64(xxh3_64(w.data()));
  return w.take();
}

std::vector<uint8_t> encode_regions(const TetMesh& dt, std::span<const uint32_t> order,
                                    std::span<const uint8_t> region, size_t region_count) {
  if (region_count < 2) return {};
  RangeEncoder rc;
  std::vector<uint8_t> decoded;
  visit_regions(dt, order, region, decoded,
                [&](RegionModels& m, const NeighbourRegions& n, uint8_t previous, uint32_t c) -> uint8_t {
                  const uint8_t r = region[c];
                  const uint8_t guess = n.count ? n.regions[0] : previous;
                  rc.encode(m.same[same_context(n)], r == guess);
                  if (r == guess) return r;
                  const int others = n.count > 0 ? n.count - 1 : 0;
                  int at = 0;
                  while (at < others && n.regions[static_cast<size_t>(at) + 1] != r) ++at;
                  if (others > 0) {
                    rc.encode(m.among_others[static_cast<size_t>(others - 1)], at < others);
                    if (at < others) {
                      for (int k = 0; k + 1 < others; ++k) {
                        rc.encode(m.which_other[static_cast<size_t>(k)], at == k);
                        if (at == k) break;
                      }
                      return r;
                    }
                  }
                  const unsigned index = r - 1u;
                  size_t node = 1;
                  for (int b = 7; b >= 0; --b) {
                    const bool bit = (index >> b) & 1u;
                    rc.encode(m.tree[node], bit);
                    node = node * 2 + (bit ? 1 : 0);
                  }
                  return r;
                });
  return rc.finish();
}

}  // namespace dtm
