// The value coder's decoder (codec/sections/value_coder.h) on arbitrary bytes: never
// a crash, and whatever decodes is one value per point, which the encoder
// codes again into a section that decodes to the same values.
//
// Input: byte 0: which point set (a 4x4x4 block, or 300 pseudo-random
// points of a 7-bit grid, by its low bit) and the scale's step (its other
// bits, plus 1); then one layer's section, all the points in one layer.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/value_coder.h"
#include "fuzz_check.h"
#include "fuzz_point_sets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const auto& points = fuzz_point_set(data[0] & 1);
  const dtm::ValueScale scale{-1000, (data[0] >> 1) + 1};
  const std::span<const uint8_t> section(data + 1, size - 1);
  dtm::ValueDecoder decoder(scale);
  std::vector<dtm::Int128> values;
  const dtm::Status s = decoder.decode_layer(section, points, values);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(values.size() == points.size());
  for (const dtm::Int128 v : values) FUZZ_CHECK(v >= scale.offset && (v - scale.offset) % scale.step == 0);
  dtm::ValueEncoder encoder(scale);
  const std::vector<uint8_t> again = encoder.encode_layer(points, values);
  dtm::ValueDecoder check(scale);
  std::vector<dtm::Int128> back;
  FUZZ_CHECK(check.decode_layer(again, points, back).ok());
  FUZZ_CHECK(back == values);
  return 0;
}
