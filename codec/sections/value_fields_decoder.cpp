// The field table and the value sections read (spec/FORMAT.md §2.1, §3.3,
// §3.5): the decoder's side of value_fields.h.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "codec/sections/value_fields.h"
#include "codec/sections/value_fields_shared.h"
#include "codec/stream/table_framing.h"
#include "common/byte_io.h"
#include "common/checksum.h"
#include "common/parallel_for.h"

namespace dtm {
namespace {

Status table_corrupt(const std::string& what) { return corrupt("field table: " + what); }

// A lossy field's quantized values stay below this (quantize_within refuses
// more than 1e18 steps), which bounds what a damaged stream can claim.
constexpr Int128 kMaxLossyOrdered = Int128{1} << 60;

constexpr uint32_t kMaxTableBytes = 1u << 20;

std::pair<Int128, Int128> field_range(const FieldDescription& f) {
  return f.lossy ? std::pair<Int128, Int128>{0, kMaxLossyOrdered} : ordered_range(f.type);
}

bool get_i128(ByteReader& r, Int128& v) {
  uint64_t low = 0, high = 0;
  if (!r.u64(low) || !r.u64(high)) return false;
  v = static_cast<Int128>((static_cast<unsigned __int128>(high) << 64) | low);
  return true;
}

// The scaled value's ceiling: offset + v * step must stay in the field's range.
Int128 max_scaled(const FieldDescription& f, int component) {
  const ValueScale& s = f.scales[component];
  return (field_range(f).second - s.offset) / s.step;
}

Status parse_description(ByteReader& r, FieldDescription& f) {
  uint8_t name_length = 0, type = 0, components = 0, mode = 0;
  if (!r.u8(name_length)) return table_corrupt("ends inside a description");
  if (name_length == 0 || name_length > kMaxFieldNameBytes)
    return table_corrupt("a field name of bad length");
  if (r.remaining() < name_length) return table_corrupt("ends inside a field name");
  f.name.resize(name_length);
  for (char& c : f.name) {
    uint8_t b = 0;
    r.u8(b);
    c = static_cast<char>(b);
  }
  if (!r.u8(type) || !r.u8(components) || !r.u8(mode) || !r.f64(f.error_bound))
    return table_corrupt("ends inside field '" + f.name + "'");
  const std::string field = "field '" + f.name + "'";
  if (type > static_cast<uint8_t>(ValueType::kF64)) return table_corrupt(field + " has an unknown type");
  f.type = static_cast<ValueType>(type);
  if (components == 0 || components > kMaxFieldComponents)
    return table_corrupt(field + " has a bad component count");
  f.components = components;
  if (mode > 1) return table_corrupt(field + " has an unknown mode");
  f.lossy = mode == 1;
  if (f.lossy ? !(is_float(f.type) && std::isfinite(f.error_bound) && f.error_bound > 0) : f.error_bound != 0)
    return table_corrupt(field + "'s error bound contradicts its mode");
  const auto [lowest, highest] = field_range(f);
  for (int c = 0; c < f.components; ++c) {
    ValueScale s;
    if (!get_i128(r, s.offset) || !get_i128(r, s.step)) return table_corrupt("ends inside " + field);
    if (s.offset < lowest || s.offset > highest || s.step < 1 || s.step > highest - lowest + 1)
      return table_corrupt(field + "'s scale is out of its type's range");
    f.scales.push_back(s);
    if (f.lossy) {
      LossyScale l;
      if (!r.f64(l.origin) || !r.f64(l.step)) return table_corrupt("ends inside " + field);
      if (!std::isfinite(l.origin) || !std::isfinite(l.step) || !(l.step > 0))
        return table_corrupt(field + "'s lossy scale is not finite and positive");
      f.lossy_scales.push_back(l);
    }
  }
  return Status::Ok();
}

}  // namespace

Status parse_field_table(std::span<const uint8_t> bytes, std::vector<FieldDescription>& fields,
                         size_t& consumed) {
  std::span<const uint8_t> body;
  size_t whole = 0;
  DTM_RETURN_IF_ERROR(unframe_table(bytes, kMaxTableBytes, "field table", body, whole));
  ByteReader r(body);
  uint8_t count = 0;
  r.u8(count);
  if (count == 0 || count > kMaxFields) return table_corrupt("the field count is out of range");
  fields.clear();
  for (int i = 0; i < count; ++i) {
    FieldDescription f;
    DTM_RETURN_IF_ERROR(parse_description(r, f));
    for (const FieldDescription& other : fields)
      if (other.name == f.name) return table_corrupt("two fields named '" + f.name + "'");
    fields.push_back(std::move(f));
  }
  if (r.remaining() != 0) return table_corrupt("bytes left over after the last field");
  consumed = whole;
  return Status::Ok();
}

Status value_section_field_bytes(std::span<const uint8_t> section, std::span<const FieldDescription> fields,
                                 std::vector<uint64_t>& field_bytes) {
  field_bytes.assign(fields.size(), 0);
  ByteReader r(section);
  for (size_t f = 0; f < fields.size(); ++f)
    for (int c = 0; c < fields[f].components; ++c) {
      uint32_t length = 0;
      if (!r.u32(length) || !r.skip(length))
        return {StatusCode::kCorrupt, "the value section of field '" + fields[f].name + "' ends early"};
      field_bytes[f] += 4 + uint64_t{length};
    }
  if (r.remaining() != 0) return {StatusCode::kCorrupt, "bytes left over after the value section's fields"};
  return Status::Ok();
}

Status decode_chunk_values(std::span<const FieldDescription> fields, std::span<const uint8_t> section,
                           std::span<const GridPoint> known_positions,
                           std::span<const std::vector<uint64_t>> known_bits,
                           std::span<const GridPoint> positions, std::vector<FieldValues>& out) {
  NeighbourSearch search;
  search.know(known_positions);
  const std::vector<std::span<const uint64_t>> known(known_bits.begin(), known_bits.end());
  return decode_chunk_values(fields, section, known, search.layer(positions), out);
}

Status decode_chunk_values(std::span<const FieldDescription> fields, std::span<const uint8_t> section,
                           std::span<const std::span<const uint64_t>> known_bits,
                           std::span<const Neighbours> neighbours, std::vector<FieldValues>& out) {
  out.clear();
  const size_t count = neighbours.size();
  ByteReader r(section);
  std::vector<Int128> ordered, seeds;
  for (size_t f = 0; f < fields.size(); ++f) {
    const FieldDescription& d = fields[f];
    FieldValues& values = out.emplace_back(FieldValues{d, {}});
    values.bits.resize(count * static_cast<size_t>(d.components));
    const size_t known = f < known_bits.size() ? known_bits[f].size() / static_cast<size_t>(d.components) : 0;
    for (int c = 0; c < d.components; ++c) {
      uint32_t length = 0;
      if (!r.u32(length) || length > r.remaining())
        return {StatusCode::kCorrupt, "the value section of field '" + d.name + "' ends early"};
      ValueDecoder decoder(d.scales[static_cast<size_t>(c)], max_scaled(d, c));
      seeds.clear();
      for (size_t i = 0; i < known; ++i)
        seeds.push_back(known_ordered(d, c, known_bits[f][i * static_cast<size_t>(d.components) + c]));
      decoder.know(seeds);
      DTM_RETURN_IF_ERROR(decoder.decode_layer(section.subspan(r.position(), length), neighbours, ordered)
                              .with_context("field '" + d.name + "'"));
      r.skip(length);
      for (size_t i = 0; i < count; ++i)
        values.bits[i * static_cast<size_t>(d.components) + c] =
            d.lossy ? bits_of(dequantize(ordered[i], d.lossy_scales[static_cast<size_t>(c)],
                                         d.type == ValueType::kF32),
                              d.type)
                    : from_ordered(ordered[i], d.type);
    }
  }
  if (r.remaining() != 0) return {StatusCode::kCorrupt, "bytes left over after the value section's fields"};
  return Status::Ok();
}

FieldSectionDecoder::FieldSectionDecoder(std::vector<FieldDescription> fields)
    : descriptions_(std::move(fields)) {
  for (const FieldDescription& f : descriptions_)
    for (int c = 0; c < f.components; ++c) coders_.emplace_back(f.scales[c], max_scaled(f, c));
}

Status FieldSectionDecoder::decode_layer(std::span<const uint8_t> section,
                                         std::span<const GridPoint> positions,
                                         std::vector<FieldValues>& out) {
  out.clear();
  for (const FieldDescription& f : descriptions_) out.push_back({f, {}});
  const std::vector<Neighbours> neighbours = search_.layer(positions);
  // Each component's block is coded alone (its own coder, its length
  // first): their spans are found first, then the blocks are decoded on
  // every core at once (a field of 3 components, or several fields, in the
  // time of one). The error said is the one a decoder reading them in
  // order would meet first: a block's damage before a later length's.
  struct Block {
    size_t field = 0, coder = 0;  // coders_[coder] codes the field's `component`
    int component = 0;
    std::span<const uint8_t> bytes;
  };
  std::vector<Block> blocks;
  Status framing = Status::Ok();
  ByteReader r(section);
  for (size_t f = 0; f < descriptions_.size() && framing.ok(); ++f) {
    const FieldDescription& d = descriptions_[f];
    out[f].bits.resize(positions.size() * static_cast<size_t>(d.components));
    for (int c = 0; c < d.components; ++c) {
      uint32_t length = 0;
      if (!r.u32(length) || length > r.remaining()) {
        framing = {StatusCode::kCorrupt, "the value section of field '" + d.name + "' ends early"};
        break;
      }
      blocks.push_back({f, blocks.size(), c, section.subspan(r.position(), length)});
      r.skip(length);
    }
  }
  std::vector<Status> decoded(blocks.size(), Status::Ok());
  const auto decode = [&](size_t k) {
    const Block& b = blocks[k];
    const FieldDescription& d = descriptions_[b.field];
    std::vector<Int128> ordered;
    decoded[k] =
        coders_[b.coder].decode_layer(b.bytes, neighbours, ordered).with_context("field '" + d.name + "'");
    if (!decoded[k].ok()) return;
    const auto c = static_cast<size_t>(b.component), n = static_cast<size_t>(d.components);
    std::vector<uint64_t>& bits = out[b.field].bits;
    for (size_t i = 0; i < positions.size(); ++i)
      bits[i * n + c] =
          d.lossy ? bits_of(dequantize(ordered[i], d.lossy_scales[c], d.type == ValueType::kF32), d.type)
                  : from_ordered(ordered[i], d.type);
  };
  for_each_item(blocks.size(), decode);
  for (const Status& st : decoded)
    if (!st.ok()) return st;
  if (!framing.ok()) return framing;
  if (r.remaining() != 0) return {StatusCode::kCorrupt, "bytes left over after the value section's fields"};
  return Status::Ok();
}

}  // namespace dtm
