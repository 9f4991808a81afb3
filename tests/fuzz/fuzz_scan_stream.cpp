// meshinfo's parsing: the headers of arbitrary bytes, scanned without
// decoding points, never crash, and what the scan reports is consistent.
#include <cstdint>
#include <span>

#include "codec/stream/format.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const dtm::StreamSummary s = dtm::scan_stream({data, size});
  FUZZ_CHECK(s.bytes == size);
  uint64_t previous_end = dtm::kHeaderSize;
  uint32_t previous_vertices = 0;
  for (const auto& layer : s.layers) {
    FUZZ_CHECK(layer.offset >= previous_end);
    FUZZ_CHECK(layer.offset < size);
    if (layer.complete) {
      FUZZ_CHECK(layer.header.level_vertices == previous_vertices + layer.header.new_vertices);
      previous_end = layer.offset + layer.size();
      FUZZ_CHECK(previous_end <= size);
      previous_vertices = layer.header.level_vertices;
    }
  }
  return 0;
}
