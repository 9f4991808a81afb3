// The face section (spec/FORMAT.md §3.7) on arbitrary bytes, below the layer
// checksum: never a crash; a section that decodes gives every face of the
// surface a label of the table (1 .. tags + 1), and those labels re-encode
// to the same section.
//
// Input: byte 0: which point set (fuzz_point_sets.h, by bit 0), which cells
// are kept (all, by bit 1, else those whose first vertex is even, making
// more surface), the tag count (1 + bits 2-6), and by bit 7 whether the
// section is a bricked layer's (17.0, spec/FORMAT.md §3.5: three chunks as
// fuzz_chunks.h makes them, the kept cells in two regions by their third
// vertex); then the section.
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/face_coder.h"
#include "fuzz_check.h"
#include "fuzz_chunks.h"
#include "fuzz_point_sets.h"
#include "mesh/delaunay.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const dtm::TetMesh block_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(false)).value();
  static const dtm::TetMesh cloud_dt = dtm::delaunay_tetrahedralize(fuzz_point_set(true)).value();
  const dtm::TetMesh& dt = (data[0] & 1) ? cloud_dt : block_dt;
  const size_t tags = 1 + ((data[0] >> 2) & 31);
  std::vector<uint8_t> kept(dt.cells.size());
  for (size_t c = 0; c < kept.size(); ++c) kept[c] = (data[0] & 2) || dt.cells[c][0] % 2 == 0;
  const std::span<const uint8_t> section(data + 1, size - 1);
  if (data[0] & 128) {
    const size_t points = fuzz_point_set(data[0] & 1).size();
    FuzzChunks chunked;
    if (!fuzz_chunks(dt, points, section, chunked)) return 0;
    for (size_t c = 0; c < kept.size(); ++c)
      if (kept[c]) kept[c] = static_cast<uint8_t>(1 + dt.cells[c][2] % 2);
    std::vector<uint32_t> rank(points);
    for (uint32_t v = 0; v < points; ++v) rank[v] = v;
    const dtm::ChunkFaces faces = dtm::chunk_faces(dt, chunked.cells, chunked.chunk_of_cell, kept, rank);
    std::vector<uint8_t> label;
    const dtm::Status s = dtm::decode_face_chunks(chunked.sections, faces, tags, label);
    if (!s.ok()) {
      FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
      return 0;
    }
    FUZZ_CHECK(label.size() == faces.faces.size());
    for (uint8_t t : label) FUZZ_CHECK(t >= 1 && t <= tags + 1);
    // (A section whose faces all decode untagged is not the encoder's: it
    // writes none.)
    const auto again = dtm::encode_face_chunks(faces, label, tags);
    for (size_t k = 0; k < 3; ++k)
      FUZZ_CHECK(again[k].empty() ||
                 again[k] == std::vector<uint8_t>(chunked.sections[k].begin(), chunked.sections[k].end()));
    return 0;
  }
  const dtm::SurfaceFaces surface = dtm::surface_faces(dt, kept);
  std::vector<uint8_t> tag;
  const dtm::Status s = dtm::decode_face_tags(section, surface, tags, tag);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(tag.size() == surface.faces.size());
  for (uint8_t t : tag) FUZZ_CHECK(t >= 1 && t <= tags + 1);
  FUZZ_CHECK(dtm::encode_face_tags(surface, tag, tags) ==
             std::vector<uint8_t>(section.begin(), section.end()));
  return 0;
}
