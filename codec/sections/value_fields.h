// The per-vertex fields of a stream (format 5.0, spec/FORMAT.md §3.3):
// the field table that follows the stream header, and each layer's value
// section, encoder and decoder side by side. codec/sections/value_coder.h codes one
// component's values; this header says how a stream carries several fields
// of several components.
//
//   field table   = u32 table_bytes, table_bytes of descriptions, u64 XXH3
//   value section = per field, per component: u32 length, its block
//
// Values travel as raw bits of their type (an integer's two's complement, a
// float's IEEE bits), vertex-major: bits[vertex * components + component].
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "codec/sections/value_coder.h"
#include "common/grid.h"
#include "common/status.h"

namespace dtm {

inline constexpr size_t kMaxFields = 32;
inline constexpr size_t kMaxFieldNameBytes = 64;
inline constexpr int kMaxFieldComponents = 64;

struct FieldDescription {
  std::string name;
  ValueType type = ValueType::kF64;
  int components = 1;
  // Lossy (floats only): every decoded value is within error_bound of the
  // original. Lossless: bit-exact.
  bool lossy = false;
  double error_bound = 0;
  // Per component, what the whole field shares (value_coder.h).
  std::vector<ValueScale> scales;
  std::vector<LossyScale> lossy_scales;  // lossy fields only
};

// "int8" ... "float64", the names tools and spec use.
const char* value_type_name(ValueType t);
bool is_float(ValueType t);

// Raw bits of a value given as a double, and back. Integers are rounded to
// the nearest (halves away from zero); 64-bit integers beyond 2^53 are not exact
// as doubles; a value outside the type's range gives 0 (refused before, by
// check_field_values).
uint64_t bits_of(double v, ValueType t);
double value_of(uint64_t bits, ValueType t);

struct FieldValues {
  FieldDescription description;
  std::vector<uint64_t> bits;  // vertex-major
  double value(size_t vertex, int component) const {
    return value_of(bits[vertex * description.components + component], description.type);
  }
};

// kInvalidInput, naming the field, unless `fields` can make a field table
// for `points` points: at most 32 fields of distinct names of 1 to 64
// bytes, 1 to 64 components each, lossy ones of a float type within a
// positive bound, and value_counts[f] = points x components of field f.
// `holders`: what the values are on, for the message ("points", "cells").
Status check_fields(std::span<const FieldDescription> fields, std::span<const size_t> value_counts,
                    size_t points, const char* holders = "points");

// kInvalidInput, naming the field and the `each` ("point", "cell") of the
// first value that the field's type cannot hold: an integer type's NaN, an
// infinity or a value outside its range once rounded to the nearest
// integer, a float32's finite value beyond its range. (Not checked, the
// value would be stored as 0 or an infinity.)
Status check_field_values(const FieldDescription& f, std::span<const double> values, const char* each);

std::vector<uint8_t> write_field_table(std::span<const FieldDescription> fields);
// Parses the table at the start of `bytes`: kNeedMoreInput until it is all
// there, kCorrupt for a damaged one. `consumed` is its size in bytes.
Status parse_field_table(std::span<const uint8_t> bytes, std::vector<FieldDescription>& fields,
                         size_t& consumed);

// Each field's bytes in a layer's value section (its length words
// included), read from the length words alone; kCorrupt if they do not add up.
Status value_section_field_bytes(std::span<const uint8_t> section, std::span<const FieldDescription> fields,
                                 std::vector<uint64_t>& field_bytes);

class FieldSectionEncoder {
 public:
  // `fields` give the values of every point the layers will name
  // (description: name, type, components, lossy, error_bound); the scales
  // are computed here. kInvalidInput for a NaN or an infinity in a lossy
  // field, or a bound too small for its values, naming the field.
  static StatusOr<FieldSectionEncoder> make(std::vector<FieldValues> fields);
  const std::vector<FieldDescription>& descriptions() const { return descriptions_; }
  // The value section of a layer whose new points are `points` (indices
  // into the fields' values) at `positions`, in the decoder's order, and in
  // `field_bytes` each field's share of it (length words included).
  std::vector<uint8_t> encode_layer(std::span<const uint32_t> points, std::span<const GridPoint> positions,
                                    std::vector<uint64_t>& field_bytes);
  // Bricked layers (8.0, spec/FORMAT.md §3.5): the value section of one
  // chunk, coded alone: fresh models, and as neighbours only the points of
  // the coarser levels in its brick (`known`, ascending Morton order, with
  // the values a decoder holds for them) and the chunk's earlier ones.
  // `field_bytes` gains each field's share.
  std::vector<uint8_t> encode_chunk(std::span<const uint32_t> known,
                                    std::span<const GridPoint> known_positions,
                                    std::span<const uint32_t> points, std::span<const GridPoint> positions,
                                    std::vector<uint64_t>& field_bytes) const;
  // The same with each point's neighbours given rather than searched
  // (indices: the known points 0.., then the chunk's points in order): the
  // edge value section's (format 19.0, spec/FORMAT.md §3.12), each node
  // predicted from its edge's corners.
  std::vector<uint8_t> encode_chunk(std::span<const uint32_t> known, std::span<const uint32_t> points,
                                    std::span<const Neighbours> neighbours,
                                    std::vector<uint64_t>& field_bytes) const;

 private:
  std::vector<FieldDescription> descriptions_;
  std::vector<std::vector<Int128>> ordered_;  // per component of every field, per point
  std::vector<ValueEncoder> coders_;          // per component of every field
  NeighbourSearch search_;                    // shared by every component
};

// A chunk's value section (FieldSectionEncoder::encode_chunk), given the
// known points' positions and their decoded values (per field, vertex-major
// bits). kCorrupt if the section is damaged.
Status decode_chunk_values(std::span<const FieldDescription> fields, std::span<const uint8_t> section,
                           std::span<const GridPoint> known_positions,
                           std::span<const std::vector<uint64_t>> known_bits,
                           std::span<const GridPoint> positions, std::vector<FieldValues>& out);
// The same with each point's neighbours given (as encode_chunk's).
Status decode_chunk_values(std::span<const FieldDescription> fields, std::span<const uint8_t> section,
                           std::span<const std::span<const uint64_t>> known_bits,
                           std::span<const Neighbours> neighbours, std::vector<FieldValues>& out);

class FieldSectionDecoder {
 public:
  explicit FieldSectionDecoder(std::vector<FieldDescription> fields);
  // The values of a layer's new points (at `positions`), one FieldValues
  // per field, in `out`. kCorrupt if the section is damaged.
  Status decode_layer(std::span<const uint8_t> section, std::span<const GridPoint> positions,
                      std::vector<FieldValues>& out);
  const std::vector<FieldDescription>& descriptions() const { return descriptions_; }

 private:
  std::vector<FieldDescription> descriptions_;
  std::vector<ValueDecoder> coders_;
  NeighbourSearch search_;  // shared by every component
};

}  // namespace dtm
