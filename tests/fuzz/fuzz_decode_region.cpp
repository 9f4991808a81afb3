// Decoding a region (spec/FORMAT.md §4.1) from arbitrary bytes: the first 7
// bytes pick the level and the box, the rest is the stream. Never a crash, a
// hang or an allocation the bytes do not justify; what decodes is a mesh
// over its own points, numbered within the level, having read no byte twice,
// with every field's values for every point, with tagged faces (17.0) every
// face's label one of the table's, with regions (15.0) every
// cell's region one of the table's, and with cell data (16.0) every cell's
// values at level 0, none at another.
// (That the region equals the whole level filtered holds for the streams the
// encoder writes, tests/test_bricks.cpp: a hostile stream may claim a kept
// radius its cells break, which only the whole decode can see.)
#include <cstdint>
#include <span>

#include "codec/region_decode.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 7) return 0;
  const int level = data[0] % 4;
  dtm::GridBox box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = int64_t{data[1 + a]} * 64 - 512;
    box.hi[a] = box.lo[a] + int64_t{data[4 + a]} * 64;
  }
  const std::span<const uint8_t> stream(data + 7, size - 7);
  dtm::DecoderOptions options;
  options.max_vertices = 4096;
  dtm::MemorySource source(stream);
  const auto region = dtm::decode_region(source, box, level, options);
  if (!region.ok()) return 0;
  FUZZ_CHECK(region->bytes_read <= stream.size());
  FUZZ_CHECK(region->points.size() == region->vertex_ids.size());
  FUZZ_CHECK(region->points.size() == region->vertex_levels.size());
  for (size_t i = 1; i < region->vertex_ids.size(); ++i)
    FUZZ_CHECK(region->vertex_ids[i] > region->vertex_ids[i - 1]);
  for (const auto& c : region->cells)
    for (uint32_t v : c) FUZZ_CHECK(v < region->points.size());
  for (const auto& f : region->fields)  // values in chunks: every point's, whole
    FUZZ_CHECK(f.bits.size() == region->points.size() * static_cast<size_t>(f.description.components));
  if (!region->cell_regions.empty() || !region->regions.empty()) {
    FUZZ_CHECK(region->cell_regions.size() == region->cells.size() || region->regions.size() < 2);
    for (uint8_t r : region->cell_regions) FUZZ_CHECK(r >= 1 && r <= region->regions.size());
  }
  // With tagged faces (17.0): each a face of a cell here, its label one of the table's.
  FUZZ_CHECK(region->face_labels.size() == region->faces.size());
  FUZZ_CHECK(region->faces.empty() || !region->face_tags.empty());
  for (size_t f = 0; f < region->faces.size(); ++f) {
    for (uint32_t v : region->faces[f]) FUZZ_CHECK(v < region->points.size());
    FUZZ_CHECK(region->face_labels[f] >= 2 && region->face_labels[f] <= region->face_tags.size() + 1);
  }
  FUZZ_CHECK(region->cell_fields.empty() || level == 0);
  for (const auto& f : region->cell_fields)
    FUZZ_CHECK(f.bits.size() == region->cells.size() * static_cast<size_t>(f.description.components));
  return 0;
}
