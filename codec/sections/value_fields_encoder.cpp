// The field table and the value sections written (spec/FORMAT.md §2.1,
// §3.3, §3.5): the encoder's side of value_fields.h.
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
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

void put_i128(ByteWriter& w, Int128 v) {
  const auto u = static_cast<unsigned __int128>(v);
  w.u64(static_cast<uint64_t>(u));
  w.u64(static_cast<uint64_t>(u >> 64));
}

}  // namespace

Status check_fields(std::span<const FieldDescription> fields, std::span<const size_t> value_counts,
                    size_t points, const char* holders) {
  if (fields.size() > kMaxFields)
    return invalid_input("the input has " + std::to_string(fields.size()) +
                         " fields; a stream holds at most " + std::to_string(kMaxFields));
  for (size_t i = 0; i < fields.size(); ++i) {
    const FieldDescription& f = fields[i];
    const std::string field = "field '" + f.name + "'";
    if (f.name.empty() || f.name.size() > kMaxFieldNameBytes)
      return invalid_input(field + ": a field's name must have 1 to 64 bytes");
    for (size_t j = 0; j < i; ++j)
      if (fields[j].name == f.name) return invalid_input("two fields are named '" + f.name + "'");
    if (f.components < 1 || f.components > kMaxFieldComponents)
      return invalid_input(field + " has " + std::to_string(f.components) + " components (1 to 64)");
    if (value_counts[i] != points * f.components)
      return invalid_input(field + " has " + std::to_string(value_counts[i]) + " values for " +
                           std::to_string(points) + " " + holders + " of " + std::to_string(f.components) +
                           " components");
    if (static_cast<uint8_t>(f.type) > static_cast<uint8_t>(ValueType::kF64))
      return invalid_input(field + " has the type number " + std::to_string(static_cast<int>(f.type)) +
                           ", which is none (int8 to float64)");
    if (f.lossy && !is_float(f.type))
      return invalid_input(field + " holds " + value_type_name(f.type) +
                           " values: only float fields can be lossy");
    if (f.lossy && !(f.error_bound > 0 && std::isfinite(f.error_bound)))
      return invalid_input(field + ": the error bound must be positive");
  }
  return Status::Ok();
}

Status check_field_values(const FieldDescription& f, std::span<const double> values, const char* each) {
  if (f.type == ValueType::kF64 || f.components < 1) return Status::Ok();
  const bool single = f.type == ValueType::kF32;
  // (ordered_range's bounds as doubles: 2^63 and 2^64 round up; the 64-bit
  // types stop at 2^53 below.)
  const auto [lowest, highest] = ordered_range(f.type);
  const double low = static_cast<double>(lowest), high = static_cast<double>(highest);
  for (size_t i = 0; i < values.size(); ++i) {
    const double v = values[i];
    std::string why;
    // A float32 keeps NaN and the infinities, and a finite double that
    // rounds to a finite float (FLT_MAX's text forms, 3.4028235e+38, lie a
    // little above it); an integer holds neither NaN nor an infinity.
    if (single) {
      // (The largest double that rounds to FLT_MAX lies half its ulp, 2^103,
      // above it, a tie rounding up to the even infinity; a double beyond a
      // float's range is not converted, which C++ leaves undefined.)
      constexpr double kBeyond = static_cast<double>(std::numeric_limits<float>::max()) + 0x1p103;
      if (!std::isfinite(v) || std::abs(v) < kBeyond) continue;
      why = ", which is not a float32 value (beyond float32's range)";
    } else {
      const double kept = std::round(v);
      const bool wide = f.type == ValueType::kI64 || f.type == ValueType::kU64;
      // (Values come as doubles: beyond 2^53 a 64-bit integer may already
      // be another one, a reader's or the caller's rounding, unseen here.)
      if (wide && std::isfinite(kept) && std::abs(kept) > 0x1p53)
        why = ", beyond 2^53: a " + std::string(value_type_name(f.type)) +
              " value so large cannot be kept exactly (it passes through a double)";
      else if (std::isfinite(kept) && kept >= low && kept <= high)
        continue;
      else
        why = ", which is not a " + std::string(value_type_name(f.type)) + " value";
    }
    std::ostringstream value;
    value << std::setprecision(17) << v;
    return invalid_input("field '" + f.name + "': " + each + " " + std::to_string(i / f.components) +
                         " holds " + value.str() + why);
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
  return frame_table(body.data());
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
  // Each component is coded alone, by its own coder: all of them at once,
  // on the threads the work holds, then written in order.
  std::vector<std::vector<uint8_t>> blocks(coders_.size());
  const auto encode = [&](size_t coder) {
    std::vector<Int128> layer;
    layer.reserve(points.size());
    for (uint32_t p : points) layer.push_back(ordered_[coder][p]);
    blocks[coder] = coders_[coder].encode_layer(neighbours, layer);
  };
  for_each_item(coders_.size(), encode);
  ByteWriter w;
  size_t coder = 0;
  for (size_t f = 0; f < descriptions_.size(); ++f) {
    const size_t before = w.data().size();
    for (int c = 0; c < descriptions_[f].components; ++c, ++coder) {
      w.u32(static_cast<uint32_t>(blocks[coder].size()));
      w.bytes(blocks[coder]);
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
  NeighbourSearch search;
  search.know(known_positions);
  return encode_chunk(known, points, search.layer(positions), field_bytes);
}

std::vector<uint8_t> FieldSectionEncoder::encode_chunk(std::span<const uint32_t> known,
                                                       std::span<const uint32_t> points,
                                                       std::span<const Neighbours> neighbours,
                                                       std::vector<uint64_t>& field_bytes) const {
  field_bytes.resize(descriptions_.size(), 0);
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

}  // namespace dtm
