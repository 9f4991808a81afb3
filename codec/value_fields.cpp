#include "codec/value_fields.h"

#include <cmath>
#include <utility>

#include "common/byte_io.h"
#include "common/checksum.h"

namespace dtm {
namespace {

Status corrupt(const std::string& what) { return {StatusCode::kCorrupt, "field table: " + what}; }

// A lossy field's quantized values stay below this (quantize_within refuses
// more than 1e18 steps), which bounds what a damaged stream can claim.
constexpr Int128 kMaxLossyOrdered = Int128{1} << 60;

constexpr uint32_t kMaxTableBytes = 1u << 20;

// The smallest and largest ordered integers of a type (to_ordered's range).
std::pair<Int128, Int128> ordered_range(ValueType t) {
  switch (t) {
    case ValueType::kI8:
      return {INT8_MIN, INT8_MAX};
    case ValueType::kU8:
      return {0, UINT8_MAX};
    case ValueType::kI16:
      return {INT16_MIN, INT16_MAX};
    case ValueType::kU16:
      return {0, UINT16_MAX};
    case ValueType::kI32:
    case ValueType::kF32:
      return {INT32_MIN, INT32_MAX};
    case ValueType::kU32:
      return {0, UINT32_MAX};
    case ValueType::kI64:
    case ValueType::kF64:
      return {INT64_MIN, INT64_MAX};
    case ValueType::kU64:
      return {0, UINT64_MAX};
  }
  return {0, 0};
}

std::pair<Int128, Int128> field_range(const FieldDescription& f) {
  return f.lossy ? std::pair<Int128, Int128>{0, kMaxLossyOrdered} : ordered_range(f.type);
}

void put_i128(ByteWriter& w, Int128 v) {
  const auto u = static_cast<unsigned __int128>(v);
  w.u64(static_cast<uint64_t>(u));
  w.u64(static_cast<uint64_t>(u >> 64));
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

// What a chunk's predictor knows of a coarser point's value (spec §3.5):
// its ordered integer, for a lossy field the quantized value nearest the
// decoded one, from the decoded bits alone (encoder and decoder agree).
Int128 known_ordered(const FieldDescription& f, int component, uint64_t decoded_bits) {
  if (!f.lossy) return to_ordered(decoded_bits, f.type);
  const LossyScale& s = f.lossy_scales[static_cast<size_t>(component)];
  return static_cast<Int128>(std::llround((value_of(decoded_bits, f.type) - s.origin) / s.step));
}

Status parse_description(ByteReader& r, FieldDescription& f) {
  uint8_t name_length = 0, type = 0, components = 0, mode = 0;
  if (!r.u8(name_length)) return corrupt("ends inside a description");
  if (name_length == 0 || name_length > kMaxFieldNameBytes) return corrupt("a field name of bad length");
  if (r.remaining() < name_length) return corrupt("ends inside a field name");
  f.name.resize(name_length);
  for (char& c : f.name) {
    uint8_t b = 0;
    r.u8(b);
    c = static_cast<char>(b);
  }
  if (!r.u8(type) || !r.u8(components) || !r.u8(mode) || !r.f64(f.error_bound))
    return corrupt("ends inside field '" + f.name + "'");
  const std::string field = "field '" + f.name + "'";
  if (type > static_cast<uint8_t>(ValueType::kF64)) return corrupt(field + " has an unknown type");
  f.type = static_cast<ValueType>(type);
  if (components == 0 || components > kMaxFieldComponents)
    return corrupt(field + " has a bad component count");
  f.components = components;
  if (mode > 1) return corrupt(field + " has an unknown mode");
  f.lossy = mode == 1;
  if (f.lossy ? !(is_float(f.type) && std::isfinite(f.error_bound) && f.error_bound > 0) : f.error_bound != 0)
    return corrupt(field + "'s error bound contradicts its mode");
  const auto [lowest, highest] = field_range(f);
  for (int c = 0; c < f.components; ++c) {
    ValueScale s;
    if (!get_i128(r, s.offset) || !get_i128(r, s.step)) return corrupt("ends inside " + field);
    if (s.offset < lowest || s.offset > highest || s.step < 1 || s.step > highest - lowest + 1)
      return corrupt(field + "'s scale is out of its type's range");
    f.scales.push_back(s);
    if (f.lossy) {
      LossyScale l;
      if (!r.f64(l.origin) || !r.f64(l.step)) return corrupt("ends inside " + field);
      if (!std::isfinite(l.origin) || !std::isfinite(l.step) || !(l.step > 0))
        return corrupt(field + "'s lossy scale is not finite and positive");
      f.lossy_scales.push_back(l);
    }
  }
  return Status::Ok();
}

// std::bit_cast, which the WebAssembly build's libc++ (emscripten 3.1.6)
// does not have yet; the compiler builtin behind it is in both compilers.
template <class To, class From>
To bit_cast(const From& from) {
  return __builtin_bit_cast(To, from);
}

}  // namespace

const char* value_type_name(ValueType t) {
  constexpr const char* kNames[] = {"int8",   "uint8", "int16",  "uint16",  "int32",
                                    "uint32", "int64", "uint64", "float32", "float64"};
  return kNames[static_cast<int>(t)];
}

bool is_float(ValueType t) { return t == ValueType::kF32 || t == ValueType::kF64; }

uint64_t bits_of(double v, ValueType t) {
  switch (t) {
    case ValueType::kF32:
      return bit_cast<uint32_t>(static_cast<float>(v));
    case ValueType::kF64:
      return bit_cast<uint64_t>(v);
    case ValueType::kU64:
      return std::isfinite(v) && v >= 0 && v < 0x1p64 ? static_cast<uint64_t>(v) : 0;
    default: {
      // Every narrower integer fits an int64; its two's complement bits.
      const auto [lowest, highest] = ordered_range(t);
      if (!std::isfinite(v) || v < static_cast<double>(lowest) || v > static_cast<double>(highest)) return 0;
      return static_cast<uint64_t>(static_cast<int64_t>(v));
    }
  }
}

double value_of(uint64_t bits, ValueType t) {
  switch (t) {
    case ValueType::kF32:
      return bit_cast<float>(static_cast<uint32_t>(bits));
    case ValueType::kF64:
      return bit_cast<double>(bits);
    case ValueType::kU64:
      return static_cast<double>(bits);
    default:
      return static_cast<double>(to_ordered(bits, t));
  }
}

Status check_fields(std::span<const FieldDescription> fields, std::span<const size_t> value_counts,
                    size_t points) {
  const auto invalid = [](const std::string& what) { return Status{StatusCode::kInvalidInput, what}; };
  if (fields.size() > kMaxFields)
    return invalid("the input has " + std::to_string(fields.size()) + " fields; a stream holds at most " +
                   std::to_string(kMaxFields));
  for (size_t i = 0; i < fields.size(); ++i) {
    const FieldDescription& f = fields[i];
    const std::string field = "field '" + f.name + "'";
    if (f.name.empty() || f.name.size() > kMaxFieldNameBytes)
      return invalid(field + ": a field's name must have 1 to 64 bytes");
    for (size_t j = 0; j < i; ++j)
      if (fields[j].name == f.name) return invalid("two fields are named '" + f.name + "'");
    if (f.components < 1 || f.components > kMaxFieldComponents)
      return invalid(field + " has " + std::to_string(f.components) + " components (1 to 64)");
    if (value_counts[i] != points * f.components)
      return invalid(field + " has " + std::to_string(value_counts[i]) + " values for " +
                     std::to_string(points) + " points of " + std::to_string(f.components) + " components");
    if (f.lossy && !is_float(f.type))
      return invalid(field + " holds " + value_type_name(f.type) + " values: only float fields can be lossy");
    if (f.lossy && !(f.error_bound > 0 && std::isfinite(f.error_bound)))
      return invalid(field + ": the error bound must be positive");
  }
  return Status::Ok();
}

std::vector<uint8_t> write_field_table(std::span<const FieldDescription> fields) {
  ByteWriter body;
  body.u8(static_cast<uint8_t>(fields.size()));
  for (const FieldDescription& f : fields) {
    body.u8(static_cast<uint8_t>(f.name.size()));
    for (char c : f.name) body.u8(static_cast<uint8_t>(c));
    body.u8(static_cast<uint8_t>(f.type));
    body.u8(static_cast<uint8_t>(f.components));
    body.u8(f.lossy ? 1 : 0);
    body.f64(f.error_bound);
    for (int c = 0; c < f.components; ++c) {
      put_i128(body, f.scales[c].offset);
      put_i128(body, f.scales[c].step);
      if (f.lossy) {
        body.f64(f.lossy_scales[c].origin);
        body.f64(f.lossy_scales[c].step);
      }
    }
  }
  ByteWriter w;
  w.u32(static_cast<uint32_t>(body.data().size()));
  w.bytes(body.data());
  w.u64(xxh3_64(w.data()));
  return w.take();
}

Status parse_field_table(std::span<const uint8_t> bytes, std::vector<FieldDescription>& fields,
                         size_t& consumed) {
  ByteReader head(bytes);
  uint32_t table_bytes = 0;
  if (!head.u32(table_bytes)) return {StatusCode::kNeedMoreInput, "field table incomplete"};
  if (table_bytes == 0 || table_bytes > kMaxTableBytes) return corrupt("its length is out of range");
  const size_t whole = 4 + size_t{table_bytes} + 8;
  if (bytes.size() < whole) return {StatusCode::kNeedMoreInput, "field table incomplete"};
  ByteReader tail(bytes.subspan(whole - 8, 8));
  uint64_t checksum = 0;
  tail.u64(checksum);
  if (checksum != xxh3_64(bytes.first(whole - 8))) return corrupt("checksum mismatch");

  ByteReader r(bytes.subspan(4, table_bytes));
  uint8_t count = 0;
  r.u8(count);
  if (count == 0 || count > kMaxFields) return corrupt("the field count is out of range");
  fields.clear();
  for (int i = 0; i < count; ++i) {
    FieldDescription f;
    DTM_RETURN_IF_ERROR(parse_description(r, f));
    for (const FieldDescription& other : fields)
      if (other.name == f.name) return corrupt("two fields named '" + f.name + "'");
    fields.push_back(std::move(f));
  }
  if (r.remaining() != 0) return corrupt("bytes left over after the last field");
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

StatusOr<FieldSectionEncoder> FieldSectionEncoder::make(std::vector<FieldValues> fields) {
  FieldSectionEncoder e;
  for (FieldValues& f : fields) {
    FieldDescription& d = f.description;
    const int n = d.components;
    const size_t points = n > 0 ? f.bits.size() / n : 0;
    d.scales.clear();
    d.lossy_scales.clear();
    for (int c = 0; c < n; ++c) {
      std::vector<Int128> ordered;
      ordered.reserve(points);
      if (d.lossy) {
        std::vector<double> values;
        values.reserve(points);
        for (size_t p = 0; p < points; ++p) values.push_back(value_of(f.bits[p * n + c], d.type));
        LossyScale lossy;
        auto q = quantize_within(values, d.error_bound, d.type == ValueType::kF32, lossy);
        if (!q.ok())
          return Status{StatusCode::kInvalidInput, "field '" + d.name + "': " + q.status().message()};
        ordered = std::move(*q);
        d.lossy_scales.push_back(lossy);
      } else {
        for (size_t p = 0; p < points; ++p) ordered.push_back(to_ordered(f.bits[p * n + c], d.type));
      }
      d.scales.push_back(value_scale(ordered));
      e.coders_.emplace_back(d.scales.back());
      e.ordered_.push_back(std::move(ordered));
    }
    e.descriptions_.push_back(std::move(d));
  }
  return e;
}

std::vector<uint8_t> FieldSectionEncoder::encode_layer(std::span<const uint32_t> points,
                                                       std::span<const GridPoint> positions,
                                                       std::vector<uint64_t>& field_bytes) {
  field_bytes.assign(descriptions_.size(), 0);
  const std::vector<Neighbours> neighbours = search_.layer(positions);
  ByteWriter w;
  size_t coder = 0;
  for (size_t f = 0; f < descriptions_.size(); ++f) {
    const size_t before = w.data().size();
    for (int c = 0; c < descriptions_[f].components; ++c, ++coder) {
      std::vector<Int128> layer;
      layer.reserve(points.size());
      for (uint32_t p : points) layer.push_back(ordered_[coder][p]);
      const std::vector<uint8_t> block = coders_[coder].encode_layer(neighbours, layer);
      w.u32(static_cast<uint32_t>(block.size()));
      w.bytes(block);
    }
    field_bytes[f] += w.data().size() - before;
  }
  return w.take();
}

std::vector<uint8_t> FieldSectionEncoder::encode_chunk(std::span<const uint32_t> known,
                                                       std::span<const GridPoint> known_positions,
                                                       std::span<const uint32_t> points,
                                                       std::span<const GridPoint> positions,
                                                       std::vector<uint64_t>& field_bytes) const {
  field_bytes.resize(descriptions_.size(), 0);
  NeighbourSearch search;
  search.know(known_positions);
  const std::vector<Neighbours> neighbours = search.layer(positions);
  ByteWriter w;
  size_t coder = 0;
  for (size_t f = 0; f < descriptions_.size(); ++f) {
    const FieldDescription& d = descriptions_[f];
    const size_t before = w.data().size();
    for (int c = 0; c < d.components; ++c, ++coder) {
      ValueEncoder encoder(d.scales[static_cast<size_t>(c)]);
      std::vector<Int128> seeds;
      seeds.reserve(known.size());
      for (uint32_t p : known) {
        const Int128 v = ordered_[coder][p];
        // The bits a decoder holds for the point.
        const uint64_t bits =
            d.lossy
                ? bits_of(dequantize(v, d.lossy_scales[static_cast<size_t>(c)], d.type == ValueType::kF32),
                          d.type)
                : from_ordered(v, d.type);
        seeds.push_back(known_ordered(d, c, bits));
      }
      encoder.know(seeds);
      std::vector<Int128> values;
      values.reserve(points.size());
      for (uint32_t p : points) values.push_back(ordered_[coder][p]);
      const std::vector<uint8_t> block = encoder.encode_layer(neighbours, values);
      w.u32(static_cast<uint32_t>(block.size()));
      w.bytes(block);
    }
    field_bytes[f] += w.data().size() - before;
  }
  return w.take();
}

Status decode_chunk_values(std::span<const FieldDescription> fields, std::span<const uint8_t> section,
                           std::span<const GridPoint> known_positions,
                           std::span<const std::vector<uint64_t>> known_bits,
                           std::span<const GridPoint> positions, std::vector<FieldValues>& out) {
  out.clear();
  NeighbourSearch search;
  search.know(known_positions);
  const std::vector<Neighbours> neighbours = search.layer(positions);
  ByteReader r(section);
  std::vector<Int128> ordered, seeds;
  for (size_t f = 0; f < fields.size(); ++f) {
    const FieldDescription& d = fields[f];
    FieldValues& values = out.emplace_back(FieldValues{d, {}});
    values.bits.resize(positions.size() * static_cast<size_t>(d.components));
    for (int c = 0; c < d.components; ++c) {
      uint32_t length = 0;
      if (!r.u32(length) || length > r.remaining())
        return {StatusCode::kCorrupt, "the value section of field '" + d.name + "' ends early"};
      ValueDecoder decoder(d.scales[static_cast<size_t>(c)], max_scaled(d, c));
      seeds.clear();
      for (size_t i = 0; i < known_positions.size(); ++i)
        seeds.push_back(known_ordered(d, c, known_bits[f][i * static_cast<size_t>(d.components) + c]));
      decoder.know(seeds);
      DTM_RETURN_IF_ERROR(decoder.decode_layer(section.subspan(r.position(), length), neighbours, ordered)
                              .with_context("field '" + d.name + "'"));
      r.skip(length);
      for (size_t i = 0; i < positions.size(); ++i)
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
  ByteReader r(section);
  size_t coder = 0;
  std::vector<Int128> ordered;
  for (size_t f = 0; f < descriptions_.size(); ++f) {
    const FieldDescription& d = descriptions_[f];
    std::vector<uint64_t>& bits = out[f].bits;
    for (int c = 0; c < d.components; ++c, ++coder) {
      uint32_t length = 0;
      if (!r.u32(length) || length > r.remaining())
        return {StatusCode::kCorrupt, "the value section of field '" + d.name + "' ends early"};
      DTM_RETURN_IF_ERROR(coders_[coder]
                              .decode_layer(section.subspan(r.position(), length), neighbours, ordered)
                              .with_context("field '" + d.name + "'"));
      r.skip(length);
      if (c == 0) bits.resize(positions.size() * d.components);
      for (size_t i = 0; i < positions.size(); ++i) {
        const uint64_t b =
            d.lossy ? bits_of(dequantize(ordered[i], d.lossy_scales[c], d.type == ValueType::kF32), d.type)
                    : from_ordered(ordered[i], d.type);
        bits[i * d.components + c] = b;
      }
    }
  }
  if (r.remaining() != 0) return {StatusCode::kCorrupt, "bytes left over after the value section's fields"};
  return Status::Ok();
}

}  // namespace dtm
