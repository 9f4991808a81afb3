// The field table and the value section (spec/FORMAT.md §2.1, §3.3) on
// arbitrary bytes, below the checksums that keep the stream targets from
// reaching them damaged: never a crash, never an allocation the bytes do not
// justify; a table that parses writes back to the same bytes, and a section
// that decodes gives every field's values for every point, in range.
//
// Input: byte 0: which point set (fuzz_point_sets.h, by its low bit); bytes
// 1-2: the table's body length n (little-endian); then n bytes of body (the
// target adds the length word and the checksum), then one value section.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/sections/value_fields.h"
#include "fuzz_check.h"
#include "fuzz_point_sets.h"
#include "fuzz_tables.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const auto& points = fuzz_point_set(data[0] & 1);
  const FuzzTable framed = fuzz_table(data, size);
  const std::vector<uint8_t>& table = framed.table;
  std::vector<dtm::FieldDescription> fields;
  size_t consumed = 0;
  const dtm::Status parsed = dtm::parse_field_table(table, fields, consumed);
  if (!parsed.ok()) {
    FUZZ_CHECK(parsed.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(consumed == table.size());
  FUZZ_CHECK(dtm::write_field_table(fields) == table);

  const std::span<const uint8_t> section = framed.after;
  std::vector<uint64_t> field_bytes;
  const dtm::Status sized = dtm::value_section_field_bytes(section, fields, field_bytes);
  dtm::FieldSectionDecoder decoder(fields);
  std::vector<dtm::FieldValues> values;
  const dtm::Status s = decoder.decode_layer(section, points, values);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  FUZZ_CHECK(sized.ok());
  FUZZ_CHECK(values.size() == fields.size());
  for (size_t f = 0; f < fields.size(); ++f)
    FUZZ_CHECK(values[f].bits.size() == points.size() * fields[f].components);
  return 0;
}
