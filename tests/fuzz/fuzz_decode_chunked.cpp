// Incremental decoding: the stream fed in chunks of random sizes (drawn from
// the input's first two bytes) must give exactly what one whole feed gives.
#include <cstdint>
#include <span>

#include "codec/decode.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  uint32_t seed = data[0] | (data[1] << 8);
  const std::span<const uint8_t> stream(data + 2, size - 2);
  dtm::DecoderOptions options;
  options.max_vertices = 4096;

  dtm::ProgressiveDecoder whole(options);
  const dtm::Status whole_status = dtm::decode_stream(stream, whole);

  dtm::ProgressiveDecoder pieces(options);
  size_t at = 0;
  int callbacks = 0;
  dtm::Status s;
  while (at < stream.size() && s.ok()) {
    seed = seed * 1103515245u + 12345u;
    const size_t chunk = std::min<size_t>(stream.size() - at, 1 + (seed >> 16) % 97);
    s = pieces.feed(stream.subspan(at, chunk),
                    [&](const dtm::ProgressiveDecoder&, const dtm::DecodedLevel&) { ++callbacks; });
    at += chunk;
  }
  const dtm::Status pieces_status = s.ok() ? pieces.finish() : s;
  FUZZ_CHECK(whole_status.code() == pieces_status.code());
  FUZZ_CHECK(whole.levels().size() == pieces.levels().size());
  FUZZ_CHECK(callbacks == static_cast<int>(pieces.levels().size()));
  for (size_t i = 0; i < whole.levels().size(); ++i) {
    FUZZ_CHECK(whole.levels()[i].level == pieces.levels()[i].level);
    FUZZ_CHECK(whole.levels()[i].vertices == pieces.levels()[i].vertices);
  }
  FUZZ_CHECK(whole.points() == pieces.points());
  return 0;
}
