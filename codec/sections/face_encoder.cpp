// The face tag sections written (spec/FORMAT.md §3.7): the encoder's side
// of face_coder.h.
#include <algorithm>
#include <vector>

#include "codec/sections/face_coder.h"
#include "codec/sections/label_coder.h"

namespace dtm {

std::vector<uint8_t> encode_face_tags(const SurfaceFaces& surface, std::span<const uint8_t> tag,
                                      size_t tags) {
  if (std::all_of(tag.begin(), tag.end(), [](uint8_t t) { return t == 1; })) return {};
  std::vector<uint32_t> order(surface.faces.size());
  for (uint32_t f = 0; f < order.size(); ++f) order[f] = f;
  RangeEncoder rc;
  std::vector<uint8_t> decoded;
  visit_labels(
      surface.faces.size(), order, {}, [&](uint32_t f) { return surface.neighbours.row(f); }, decoded,
      [&](LabelModels& m, const NeighbourLabels& n, uint8_t previous, uint32_t f) {
        encode_label(rc, m, n, previous, tag[f]);
        return tag[f];
      });
  return rc.finish();
}

}  // namespace dtm
