// The layer coder's payload decoder on arbitrary bytes, below the layer
// checksum that keeps the stream-level targets from ever reaching it with a
// damaged payload: never a crash, and whatever decodes is a valid layer
// (distinct points in the grid, none known, as many as asked).
//
// Input: byte 0: qbits (1..24) and the format (bit 7: 3.0, else 2.0);
// byte 1: the number of known points (0..31); byte 2: the point count
// (1..64); then 6 bytes per known point, then the payload.
#include <algorithm>
#include <cstdint>
#include <set>
#include <span>
#include <vector>

#include "codec/stream/layer_coder.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const int qbits = 1 + (data[0] & 0x7F) % 24;
  const bool format3 = data[0] & 0x80;
  const size_t known_count = data[1] % 32;
  const uint32_t count = 1 + data[2] % 64;
  size_t pos = 3;
  const uint32_t mask = (uint32_t{1} << qbits) - 1;
  std::set<dtm::GridPoint> known_set;
  for (size_t i = 0; i < known_count && pos + 6 <= size; ++i, pos += 6) {
    const auto coordinate = [&](size_t at) {
      return static_cast<int32_t>((data[at] | data[at + 1] << 8) & mask);
    };
    known_set.insert({coordinate(pos), coordinate(pos + 2), coordinate(pos + 4)});
  }
  const std::vector<dtm::GridPoint> known(known_set.begin(), known_set.end());
  std::vector<dtm::MortonCode> codes;
  dtm::merge_known(codes, known, qbits);
  dtm::SetCoderModels models;
  if (format3) models.enable_coordinate_reuse(qbits);
  std::vector<dtm::GridPoint> out;
  const dtm::Status s =
      dtm::decode_point_set(std::span(data + pos, size - pos), codes, qbits, count, models, out);
  FUZZ_CHECK(out.size() <= count);
  if (!s.ok()) return 0;
  FUZZ_CHECK(out.size() == count);
  std::set<dtm::GridPoint> distinct(out.begin(), out.end());
  FUZZ_CHECK(distinct.size() == out.size());
  for (const auto& p : out) {
    FUZZ_CHECK(p.x >= 0 && p.y >= 0 && p.z >= 0);
    FUZZ_CHECK(static_cast<uint32_t>(p.x) <= mask && static_cast<uint32_t>(p.y) <= mask &&
               static_cast<uint32_t>(p.z) <= mask);
    FUZZ_CHECK(!known_set.count(p));
  }
  return 0;
}
