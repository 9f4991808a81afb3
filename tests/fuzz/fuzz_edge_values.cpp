// The edge value section (spec/FORMAT.md §3.12) and the field table it reads
// with, on arbitrary bytes, below the checksums that keep the stream
// targets from reaching them damaged: never a crash; a section that decodes
// gives every present node each field's values, and lossless values code
// again to a section that decodes to the same values.
//
// Input: byte 0: which point set (bit 0, fuzz_point_sets.h), which of its
// Delaunay cells the level keeps (bits 1-2: all, every other, two in three,
// one in five) and which of the level's edges have a node (bits 3-4: all,
// every other, one in three, one in seven); bytes 1-2: the table's body
// length n (little-endian); then n bytes of body (the target adds the length
// word and the checksum), then the section. The vertices' values are ones a
// decoder could hold: a lossless component's the scale's offset or the next
// step, a lossy one's the quantized 0, 1 or 2.
#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "codec/sections/edge_node_coder.h"
#include "codec/sections/value_fields_shared.h"
#include "fuzz_check.h"
#include "fuzz_level_edges.h"
#include "fuzz_point_sets.h"
#include "fuzz_tables.h"
#include "mesh/delaunay.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const bool cloud = data[0] & 1;
  const int pattern = (data[0] >> 1) & 3;
  const int nodes_every = std::array{1, 2, 3, 7}[(data[0] >> 3) & 3];
  const size_t points = fuzz_point_set(cloud).size();
  const FuzzTable framed = fuzz_table(data, size);
  std::vector<dtm::FieldDescription> fields;
  size_t consumed = 0;
  const dtm::Status parsed = dtm::parse_field_table(framed.table, fields, consumed);
  if (!parsed.ok()) {
    FUZZ_CHECK(parsed.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  const FuzzLevel level = fuzz_level(cloud, pattern);
  const dtm::LevelEdges& edges = level.edges;
  std::vector<uint8_t> present(edges.corners.size());
  for (size_t e = 0; e < present.size(); ++e) present[e] = e % static_cast<size_t>(nodes_every) == 0;
  const auto nodes = static_cast<size_t>(std::count(present.begin(), present.end(), 1));

  std::vector<dtm::FieldValues> vertices;
  for (const dtm::FieldDescription& f : fields) {
    dtm::FieldValues& v = vertices.emplace_back(dtm::FieldValues{f, {}});
    const auto n = static_cast<size_t>(f.components);
    v.bits.resize(points * n);
    for (size_t i = 0; i < points; ++i)
      for (size_t c = 0; c < n; ++c) {
        if (f.lossy) {
          v.bits[i * n + c] = dtm::bits_of(dtm::dequantize(static_cast<dtm::Int128>(i % 3), f.lossy_scales[c],
                                                           f.type == dtm::ValueType::kF32),
                                           f.type);
          continue;
        }
        const dtm::ValueScale& s = f.scales[c];
        const dtm::Int128 next = s.offset + s.step;
        const bool fits = i % 2 == 1 && next <= dtm::ordered_range(f.type).second;
        v.bits[i * n + c] = dtm::from_ordered(fits ? next : s.offset, f.type);
      }
  }
  std::vector<dtm::FieldValues> values;
  const dtm::Status s = dtm::decode_edge_node_values(framed.after, fields, vertices, edges, present, values);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(values.size() == fields.size());
  for (size_t f = 0; f < fields.size(); ++f)
    FUZZ_CHECK(values[f].bits.size() == nodes * static_cast<size_t>(fields[f].components));
  // Lossless values code again to values that decode the same (a lossy
  // table's scales are the encoder's own, not re-derived here).
  if (std::any_of(fields.begin(), fields.end(), [](const auto& f) { return f.lossy; })) return 0;
  std::vector<dtm::FieldValues> rows = vertices;  // the vertices', then the nodes'
  for (size_t f = 0; f < fields.size(); ++f)
    rows[f].bits.insert(rows[f].bits.end(), values[f].bits.begin(), values[f].bits.end());
  auto again = dtm::FieldSectionEncoder::make(rows);
  FUZZ_CHECK(again.ok());
  std::vector<uint32_t> known(points), coded(nodes);
  std::iota(known.begin(), known.end(), 0u);
  std::iota(coded.begin(), coded.end(), static_cast<uint32_t>(points));
  std::vector<uint64_t> field_bytes;
  const std::vector<uint8_t> recoded =
      again->encode_chunk(known, coded, dtm::edge_node_neighbours(edges, present), field_bytes);
  std::vector<dtm::FieldValues> back;
  FUZZ_CHECK(
      dtm::decode_edge_node_values(recoded, again->descriptions(), vertices, edges, present, back).ok());
  for (size_t f = 0; f < fields.size(); ++f) FUZZ_CHECK(back[f].bits == values[f].bits);
  return 0;
}
