// The node label section read (spec/FORMAT.md §3.14).
#include <unordered_set>

#include "codec/sections/node_label_coder.h"
#include "codec/sections/node_label_coder_shared.h"

namespace dtm {

namespace {

// As encode_magnitude() (node_label_encoder.cpp) wrote it.
uint64_t decode_magnitude(RangeDecoder& rc, NodeLabelModels& models, int least) {
  int b = least;
  while (b < 62 && rc.decode(models.longer[static_cast<size_t>(b)])) ++b;
  if (b == 0) return 0;
  return (uint64_t{1} << (b - 1)) | (b > 1 ? rc.decode_raw(b - 1) : 0);
}

Status bad_labels(const std::string& what) { return {StatusCode::kCorrupt, "node labels: " + what}; }

}  // namespace

Status decode_node_labels(std::span<const uint8_t> section, size_t count, std::vector<int64_t>& labels) {
  labels.clear();
  RangeDecoder rc(section);
  NodeLabelModels models;
  std::unordered_set<int64_t> seen;
  bool last_next = false;
  int64_t last_gap = 0;  // the last gap other than 0 (none: 0)
  for (size_t k = 0; k < count; ++k) {
    int64_t label = 0;
    if (k == 0) {
      label = static_cast<int64_t>(decode_magnitude(rc, models, 0)) + 1;
    } else {
      last_next = rc.decode(models.next[last_next ? 1 : 0]);
      if (last_next) {
        label = labels.back() + 1;
      } else {
        if (last_gap == 0 || !rc.decode(models.again)) {
          const bool down = rc.decode(models.down);
          const auto size = static_cast<int64_t>(decode_magnitude(rc, models, 1));
          last_gap = down ? -size : size;
        }
        label = labels.back() + last_gap + 1;
      }
    }
    if (rc.overran()) return bad_labels("the section ends early");
    if (label < 1 || label > kMaxNodeLabel) return bad_labels("a label out of range");
    if (!seen.insert(label).second) return bad_labels("label " + std::to_string(label) + " given twice");
    labels.push_back(label);
  }
  if (!rc.finished_cleanly()) return bad_labels("bytes after its last label's");
  return Status::Ok();
}

}  // namespace dtm
