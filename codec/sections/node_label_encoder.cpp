// The node label section written (spec/FORMAT.md §3.14): the encoder's
// side of node_label_coder.h.
#include <bit>
#include <unordered_set>

#include "codec/sections/node_label_coder.h"
#include "codec/sections/node_label_coder_shared.h"

namespace dtm {

namespace {

// A magnitude m of bit length b in [least, 62]: b as "longer" bits from
// `least` on, then m's bits below its leading one, raw.
void encode_magnitude(RangeEncoder& rc, NodeLabelModels& models, uint64_t m, int least) {
  const int b = std::bit_width(m);
  for (int j = least; j < 62; ++j) {
    rc.encode(models.longer[static_cast<size_t>(j)], b > j);
    if (b <= j) break;
  }
  if (b > 1) rc.encode_raw(m & ((uint64_t{1} << (b - 1)) - 1), b - 1);
}

}  // namespace

bool valid_node_labels(std::span<const int64_t> labels) {
  std::unordered_set<int64_t> seen;
  seen.reserve(labels.size());
  for (const int64_t l : labels)
    if (l < 1 || l > kMaxNodeLabel || !seen.insert(l).second) return false;
  return true;
}

std::vector<uint8_t> encode_node_labels(std::span<const int64_t> labels) {
  RangeEncoder rc;
  NodeLabelModels models;
  bool last_next = false;
  int64_t last_gap = 0;  // the last gap other than 0 (none: 0)
  for (size_t k = 0; k < labels.size(); ++k) {
    if (k == 0) {
      encode_magnitude(rc, models, static_cast<uint64_t>(labels[0] - 1), 0);
      continue;
    }
    const int64_t gap = labels[k] - labels[k - 1] - 1;
    rc.encode(models.next[last_next ? 1 : 0], gap == 0);
    last_next = gap == 0;
    if (gap == 0) continue;
    if (last_gap != 0) rc.encode(models.again, gap == last_gap);
    if (gap == last_gap) continue;
    last_gap = gap;
    rc.encode(models.down, gap < 0);
    encode_magnitude(rc, models, gap < 0 ? static_cast<uint64_t>(-gap) : static_cast<uint64_t>(gap), 1);
  }
  return rc.finish();
}

}  // namespace dtm
