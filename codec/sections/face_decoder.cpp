// The face tag sections read (spec/FORMAT.md §3.7): the decoder's side of
// face_coder.h.
#include <vector>

#include "codec/sections/face_coder.h"
#include "codec/sections/label_coder.h"

namespace dtm {

Status decode_face_tags(std::span<const uint8_t> section, const SurfaceFaces& surface, size_t tags,
                        std::vector<uint8_t>& tag) {
  if (section.empty()) {
    tag.assign(surface.faces.size(), 1);
    return Status::Ok();
  }
  std::vector<uint32_t> order(surface.faces.size());
  for (uint32_t f = 0; f < order.size(); ++f) order[f] = f;
  RangeDecoder rc(section);
  const bool whole = visit_labels(
      surface.faces.size(), order, {}, [&](uint32_t f) { return surface.neighbours.row(f); }, tag,
      [&](LabelModels& m, const NeighbourLabels& n, uint8_t previous, uint32_t) {
        return decode_label(rc, m, n, previous, tags + 1);
      });
  if (!whole) return {StatusCode::kCorrupt, "a face's tag is not in the face tag table"};
  if (!rc.finished_cleanly())
    return {StatusCode::kCorrupt,
            rc.overran() ? "the face section ends early" : "bytes after the face section"};
  return Status::Ok();
}

}  // namespace dtm
