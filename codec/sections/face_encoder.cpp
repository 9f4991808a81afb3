// The face tag sections written (spec/FORMAT.md §3.7): the encoder's side
// of face_coder.h.
#include <algorithm>
#include <vector>

#include "codec/sections/face_coder.h"
#include "codec/sections/label_coder.h"
#include "common/parallel_for.h"

namespace dtm {

std::vector<uint8_t> encode_face_tags(const SurfaceFaces& surface, std::span<const uint8_t> tag,
                                      size_t /*tags: the labels' bound, which the encoder needs not*/) {
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

std::vector<std::vector<uint8_t>> encode_face_chunks(const ChunkFaces& faces, std::span<const uint8_t> label,
                                                     size_t /*tags*/) {
  const size_t count = faces.first.empty() ? 0 : faces.first.size() - 1;
  std::vector<std::vector<uint8_t>> out(count);
  std::vector<uint8_t> decoded(faces.faces.size(), 0);
  parallel_for(
      count,
      [&](size_t i) {
        const uint32_t first = faces.first[i], last = faces.first[i + 1];
        if (std::all_of(label.begin() + first, label.begin() + last, [](uint8_t t) { return t == 1; }))
          return;
        std::vector<uint32_t> order(last - first);
        for (uint32_t f = first; f < last; ++f) order[f - first] = f;
        RangeEncoder rc;
        visit_label_run(
            order, {}, [&](uint32_t f) { return faces.neighbours.row(f); }, decoded,
            [&](LabelModels& m, const NeighbourLabels& n, uint8_t previous, uint32_t f) {
              encode_label(rc, m, n, previous, label[f]);
              return label[f];
            });
        out[i] = rc.finish();
      },
      2);
  return out;
}

}  // namespace dtm
