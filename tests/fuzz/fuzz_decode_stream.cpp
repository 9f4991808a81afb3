// Whole-stream decoding of arbitrary bytes: never a crash, a hang or an
// allocation the bytes do not justify; whatever decodes is a valid level.
#include <cstdint>
#include <span>

#include "codec/decode.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dtm::DecoderOptions options;
  options.max_vertices = 4096;  // keeps each run fast; the limits themselves are under test too
  options.max_values = 4096 * 8;
  dtm::ProgressiveDecoder decoder(options);
  const dtm::Status status = dtm::decode_stream({data, size}, decoder);
  if (decoder.levels().empty()) return 0;
  FUZZ_CHECK(decoder.points().size() == decoder.levels().back().vertices);
  FUZZ_CHECK(decoder.points().size() <= options.max_vertices);
  for (const auto& f : decoder.fields())
    FUZZ_CHECK(f.bits.size() == decoder.points().size() * f.description.components);
  if (status.ok()) FUZZ_CHECK(decoder.complete() || decoder.stopped());
  // The finest level decoded must triangulate and carve (this runs CGAL on
  // hostile point sets).
  const auto dt = decoder.delaunay();
  if (decoder.mesh_status().ok()) {
    for (const auto& c : decoder.carved_cells())
      for (uint32_t v : c) FUZZ_CHECK(v < decoder.points().size());
  }
  return 0;
}
