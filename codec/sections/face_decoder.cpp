// The face tag sections read (spec/FORMAT.md §3.7): the decoder's side of
// face_coder.h.
#include <algorithm>
#include <string>
#include <vector>

#include "codec/sections/face_coder.h"
#include "codec/sections/label_coder.h"
#include "common/parallel_for.h"

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

Status decode_face_chunks(std::span<const std::span<const uint8_t>> sections, const ChunkFaces& faces,
                          size_t tags, std::vector<uint8_t>& label) {
  const size_t count = sections.size();
  if (faces.first.size() != count + 1)
    return {StatusCode::kInternal, "decode_face_chunks: the chunks' faces do not match the sections"};
  label.assign(faces.faces.size(), 0);
  // Per chunk: 0 fine, 1 a tag out of the table, 2 not ending where its bytes do.
  std::vector<uint8_t> damage(count, 0);
  parallel_for(
      count,
      [&](size_t i) {
        const uint32_t first = faces.first[i], last = faces.first[i + 1];
        if (sections[i].empty()) {
          std::fill(label.begin() + first, label.begin() + last, uint8_t{1});
          return;
        }
        std::vector<uint32_t> order(last - first);
        for (uint32_t f = first; f < last; ++f) order[f - first] = f;
        RangeDecoder rc(sections[i]);
        const bool whole = visit_label_run(
            order, {}, [&](uint32_t f) { return faces.neighbours.row(f); }, label,
            [&](LabelModels& m, const NeighbourLabels& n, uint8_t previous, uint32_t) {
              return decode_label(rc, m, n, previous, tags + 1);
            });
        damage[i] = !whole ? 1 : !rc.finished_cleanly() ? 2 : 0;
      },
      2);
  static constexpr const char* kWhat[] = {"", "a face's tag is not in the face tag table",
                                          "its face section does not end where its bytes do"};
  for (size_t i = 0; i < count; ++i)
    if (damage[i]) return {StatusCode::kCorrupt, "chunk " + std::to_string(i) + ": " + kWhat[damage[i]]};
  return Status::Ok();
}

}  // namespace dtm
