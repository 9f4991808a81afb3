// Random small point sets -> hierarchy -> stream -> decoder: every decoded
// level is the encoder's (vertex set and carved cells), the decoder produces
// the vertices in the order the encoder said, and encoding twice gives the
// same bytes.
#include <cstdint>
#include <set>
#include <span>
#include <vector>

#include "codec/decode.h"
#include "codec/expert_encode.h"
#include "codec/stream/format.h"
#include "core/hierarchy.h"
#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const int qbits = 3 + data[0] % 8;  // 3..10
  const int step = 1 + data[1] % 3;
  const int32_t mask = (1 << qbits) - 1;
  std::set<dtm::GridPoint> set;
  for (size_t i = 2; i + 6 <= size && set.size() < 60; i += 6) {
    auto coord = [&](size_t k) { return static_cast<int32_t>((data[k] | (data[k + 1] << 8)) & mask); };
    set.insert({coord(i), coord(i + 2), coord(i + 4)});
  }
  const std::vector<dtm::GridPoint> points(set.begin(), set.end());
  if (points.size() < 4) return 0;
  dtm::Grid grid;
  grid.qbits = qbits;
  dtm::HierarchyOptions options;
  options.dmax = 1.0 + data[1] % 7;
  options.min_base_vertices = 4;
  options.measure_boundary_error = false;
  const auto built = dtm::build_hierarchy(points, options);
  if (!built.ok()) {
    FUZZ_CHECK(built.status().code() == dtm::StatusCode::kInvalidInput);
    return 0;  // flat input: refused, as it must be
  }
  const dtm::Hierarchy& hierarchy = *built;
  dtm::StreamOptions so;
  so.cell_hashes = true;
  so.level_step = step;
  const auto encoded = dtm::encode_stream(hierarchy, points, grid, options.alpha.kind, so);
  const auto again = dtm::encode_stream(hierarchy, points, grid, options.alpha.kind, so);
  FUZZ_CHECK(encoded.ok() && again.ok());
  const dtm::EncodedStream& first = *encoded;
  FUZZ_CHECK(first.bytes == again->bytes);

  dtm::ProgressiveDecoder decoder;
  size_t index = 0;
  const dtm::Status s =
      decoder.feed(first.bytes, [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& level) {
        const auto& want = hierarchy.levels[first.streamed_levels[level.level]];
        std::vector<dtm::GridPoint> got(d.points().begin(), d.points().end()), expected;
        for (uint32_t v : want.vertices) expected.push_back(points[v]);
        std::sort(got.begin(), got.end());
        FUZZ_CHECK(got == expected);
        FUZZ_CHECK(dtm::cell_set_hash(d.points(), d.carved_cells()) == *level.cell_hash);
        ++index;
      });
  FUZZ_CHECK(s.ok() && decoder.finish().ok());
  FUZZ_CHECK(index == first.streamed_levels.size());
  FUZZ_CHECK(first.decode_order.size() == decoder.points().size());
  for (size_t i = 0; i < first.decode_order.size(); ++i)
    FUZZ_CHECK(decoder.points()[i] == points[first.decode_order[i]]);
  return 0;
}
