// Per-vertex fields in the stream (format 5.0, spec/FORMAT.md §3.3): the
// field table, the value sections, and what the one-call encoder and the
// progressive decoder promise: lossless fields come back bit for bit at every
// level, lossy ones within their bound, and damage is refused.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/region_decode.h"
#include "codec/sections/value_fields.h"
#include "common/byte_io.h"
#include "common/checksum.h"
#include "common/threads.h"
#include "test_support.h"
#include "tools/formats/input.h"

namespace dtm {
namespace {

FieldDescription lossless(const std::string& name, ValueType type, int components = 1) {
  FieldDescription d;
  d.name = name;
  d.type = type;
  d.components = components;
  for (int c = 0; c < components; ++c) d.scales.push_back({-3 - c, 1 + c});
  return d;
}

std::vector<FieldDescription> sample_table() {
  std::vector<FieldDescription> t = {lossless("markers", ValueType::kI32),
                                     lossless("velocity", ValueType::kF64, 3)};
  FieldDescription l = lossless("pressure", ValueType::kF32);
  l.lossy = true;
  l.error_bound = 0.01;
  l.scales = {{0, 1}};
  l.lossy_scales = {{-2.5, 0.0199}};
  t.push_back(l);
  return t;
}

TEST(FieldTable, RoundTrips) {
  const auto table = sample_table();
  const auto bytes = write_field_table(table);
  std::vector<FieldDescription> read;
  size_t consumed = 0;
  ASSERT_TRUE(parse_field_table(bytes, read, consumed).ok());
  EXPECT_EQ(consumed, bytes.size());
  ASSERT_EQ(read.size(), table.size());
  for (size_t f = 0; f < table.size(); ++f) {
    EXPECT_EQ(read[f].name, table[f].name);
    EXPECT_EQ(read[f].type, table[f].type);
    EXPECT_EQ(read[f].components, table[f].components);
    EXPECT_EQ(read[f].lossy, table[f].lossy);
    EXPECT_EQ(read[f].error_bound, table[f].error_bound);
    ASSERT_EQ(read[f].scales.size(), table[f].scales.size());
    for (size_t c = 0; c < table[f].scales.size(); ++c) {
      EXPECT_TRUE(read[f].scales[c].offset == table[f].scales[c].offset);
      EXPECT_TRUE(read[f].scales[c].step == table[f].scales[c].step);
    }
  }
  EXPECT_EQ(read[2].lossy_scales[0].origin, -2.5);
  EXPECT_EQ(read[2].lossy_scales[0].step, 0.0199);
}

TEST(FieldTable, EveryPrefixWaitsAndEveryFlipIsRefused) {
  const auto bytes = write_field_table(sample_table());
  std::vector<FieldDescription> read;
  size_t consumed = 0;
  for (size_t n = 0; n < bytes.size(); ++n)
    EXPECT_EQ(parse_field_table(std::span(bytes).first(n), read, consumed).code(), StatusCode::kNeedMoreInput)
        << n;
  for (size_t i = 0; i < bytes.size(); ++i)
    for (int b = 0; b < 8; ++b) {
      auto damaged = bytes;
      damaged[i] ^= static_cast<uint8_t>(1 << b);
      const Status s = parse_field_table(damaged, read, consumed);
      // A flip in the length word may only make the table look longer.
      EXPECT_TRUE(s.code() == StatusCode::kCorrupt || (i < 4 && s.code() == StatusCode::kNeedMoreInput))
          << "byte " << i << " bit " << b << ": " << s.message();
    }
}

// A table whose checksum holds but whose content contradicts the format: a
// decoder must refuse it before it builds anything on it.
TEST(FieldTable, ContentOutOfRangeIsRefusedUnderAValidChecksum) {
  auto with_checksum = [](std::vector<FieldDescription> t) {
    auto bytes = write_field_table(t);
    ByteWriter w;
    w.bytes(std::span(bytes).first(bytes.size() - 8));
    w.u64(xxh3_64(w.data()));
    return w.take();
  };
  auto refused = [&](std::vector<FieldDescription> t) {
    std::vector<FieldDescription> read;
    size_t consumed = 0;
    return parse_field_table(with_checksum(std::move(t)), read, consumed).code() == StatusCode::kCorrupt;
  };
  auto t = sample_table();
  t[0].scales[0].offset = Int128{1} << 40;  // beyond int32
  EXPECT_TRUE(refused(t));
  t = sample_table();
  t[1].scales[1].step = 0;
  EXPECT_TRUE(refused(t));
  t = sample_table();
  t[0].lossy = true;  // an integer field cannot be lossy
  t[0].error_bound = 1;
  t[0].lossy_scales = {{0, 1}};
  EXPECT_TRUE(refused(t));
  t = sample_table();
  t[2].lossy_scales[0].step = -1;
  EXPECT_TRUE(refused(t));
  t = sample_table();
  t[2].error_bound = 0;
  EXPECT_TRUE(refused(t));
  t = sample_table();
  t[1].name = t[0].name;
  EXPECT_TRUE(refused(t));
  EXPECT_TRUE(refused({}));
  t = sample_table();
  EXPECT_FALSE(refused(t));
}

// The torus with fields of every kind: its TetGen markers (int32), a smooth
// float32 with the awkward values (NaN, infinities, -0, a denormal), a
// float64 vector, an 8-bit label and 64-bit integers beyond 2^32.
struct FieldCase {
  InputMesh mesh;
  std::vector<std::vector<double>> values;
  std::vector<EncodeInput::Field> fields;
};

FieldCase torus_with_fields() {
  FieldCase c;
  c.mesh = read_input(test::data_path("torus_288.node"));
  const auto& pts = c.mesh.points;
  const size_t n = pts.size();
  std::vector<double> smooth, vec, label, big;
  for (size_t i = 0; i < n; ++i) {
    const InputPoint& p = pts[i];
    smooth.push_back(static_cast<float>(std::exp(-(p.x * p.x + p.y * p.y)) + 0.1 * p.z));
    vec.insert(vec.end(), {std::sin(p.x), p.y * p.z, -p.x / 3});
    label.push_back(p.x > 0 ? (p.z > 0 ? 2 : 1) : 0);
    big.push_back(static_cast<double>(int64_t{1} << 40) + 3.0 * i - 500);
  }
  smooth[5] = std::numeric_limits<double>::quiet_NaN();
  smooth[6] = std::numeric_limits<double>::infinity();
  smooth[7] = -std::numeric_limits<double>::infinity();
  smooth[8] = -0.0;
  smooth[9] = std::numeric_limits<float>::denorm_min();
  c.values = {c.mesh.fields.at(0).values, smooth, vec, label, big};
  c.fields = {{"boundary_marker", ValueType::kI32, 1, c.values[0]},
              {"smooth", ValueType::kF32, 1, c.values[1]},
              {"velocity", ValueType::kF64, 3, c.values[2]},
              {"label", ValueType::kU8, 1, c.values[3]},
              {"big", ValueType::kI64, 1, c.values[4]}};
  return c;
}

EncodeOptions torus_options() {
  EncodeOptions o;
  o.scale = 25;
  o.dmax = 3;
  return o;
}

// A layer's components are coded alone, each by its own coder, and coded
// and decoded on every core at once: the same bytes and values on any
// number of threads, layer after layer (the coders carry their models
// over), and damage in one component's block refused naming its field
// (the first damaged block in order, as one thread reading them would say).
TEST(FieldSections, ComponentsCodedOnEveryThreadGiveTheSameBytesAndValues) {
  const std::vector<GridPoint> points = test::random_grid_points(6000, 12, 11);
  std::vector<FieldValues> fields(3);
  fields[0].description = lossless("velocity", ValueType::kF64, 3);
  fields[1].description = lossless("zone", ValueType::kI32);
  fields[2].description = lossless("stress", ValueType::kF32, 6);
  for (size_t i = 0; i < points.size(); ++i) {
    const double x = points[i].x * 1e-3, y = points[i].y * 1e-3, z = points[i].z * 1e-3;
    for (int c = 0; c < 3; ++c)
      fields[0].bits.push_back(bits_of(std::sin(x * (c + 1)) + y * z, ValueType::kF64));
    fields[1].bits.push_back(bits_of(static_cast<double>(i % 7), ValueType::kI32));
    for (int c = 0; c < 6; ++c)
      fields[2].bits.push_back(bits_of(static_cast<float>(x * c - y + z * z), ValueType::kF32));
  }
  // Three layers: a coarse one, then two finer.
  const std::vector<size_t> ends = {500, 2000, points.size()};
  std::vector<std::vector<uint8_t>> want;
  for (const int threads : {1, 2, 3, 8}) {
    set_thread_count(threads);
    auto coder = FieldSectionEncoder::make(fields);
    ASSERT_TRUE(coder.ok());
    std::vector<std::vector<uint8_t>> sections;
    for (size_t l = 0, first = 0; l < ends.size(); first = ends[l++]) {
      std::vector<uint32_t> ids(ends[l] - first);
      std::iota(ids.begin(), ids.end(), static_cast<uint32_t>(first));
      std::vector<uint64_t> bytes;
      sections.push_back(coder->encode_layer(ids, std::span(points).subspan(first, ids.size()), bytes));
    }
    if (want.empty()) want = sections;
    EXPECT_EQ(sections, want) << threads << " threads";
    FieldSectionDecoder decoder(coder->descriptions());
    for (size_t l = 0, first = 0; l < ends.size(); first = ends[l++]) {
      std::vector<FieldValues> out;
      ASSERT_TRUE(decoder.decode_layer(want[l], std::span(points).subspan(first, ends[l] - first), out).ok());
      ASSERT_EQ(out.size(), fields.size());
      for (size_t f = 0; f < fields.size(); ++f) {
        const auto n = static_cast<size_t>(fields[f].description.components);
        EXPECT_TRUE(std::equal(out[f].bits.begin(), out[f].bits.end(), fields[f].bits.begin() + first * n))
            << fields[f].description.name << ", layer " << l << ", " << threads << " threads";
      }
    }
  }
  // Damage: the second block of "stress" (the sixth block in order)
  // and a length running past the section. Fresh decoders each time: the
  // first layer's section.
  const auto blocks = [&](std::span<const uint8_t> section) {
    std::vector<size_t> starts;  // each block's first byte
    ByteReader r(section);
    for (uint32_t length = 0; r.u32(length) && r.skip(length);) starts.push_back(r.position() - length);
    return starts;
  };
  const std::vector<size_t> starts = blocks(want[0]);
  ASSERT_EQ(starts.size(), 10u);
  for (const int threads : {1, 2, 8}) {
    set_thread_count(threads);
    auto coder = FieldSectionEncoder::make(fields);
    std::vector<uint8_t> damaged = want[0];
    for (size_t k = 0; k < 8; ++k) damaged[starts[5] + k] ^= 0xA5;
    std::vector<FieldValues> out;
    const std::span<const GridPoint> first_layer = std::span(points).first(ends[0]);
    Status s = FieldSectionDecoder(coder->descriptions()).decode_layer(damaged, first_layer, out);
    EXPECT_EQ(s.code(), StatusCode::kCorrupt) << threads << " threads";
    EXPECT_NE(s.message().find("field 'stress'"), std::string::npos) << s.message();
    // A length past the end in "stress" after damage in "velocity": the
    // velocity's block is what a reader in order meets first.
    damaged = want[0];
    for (size_t k = 0; k < 8; ++k) damaged[starts[1] + k] ^= 0xA5;
    damaged[starts[6] - 4] = 0xFF, damaged[starts[6] - 1] = 0x7F;
    s = FieldSectionDecoder(coder->descriptions()).decode_layer(damaged, first_layer, out);
    EXPECT_EQ(s.code(), StatusCode::kCorrupt);
    EXPECT_NE(s.message().find("field 'velocity'"), std::string::npos) << s.message();
  }
  set_thread_count(0);
}

TEST(StreamValues, LosslessFieldsComeBackBitExactAtEveryLevel) {
  FieldCase c = torus_with_fields();
  EncodeInput in;
  in.points = c.mesh.points;
  in.tetrahedra = c.mesh.tets;
  in.fields = c.fields;
  const auto encoded = encode(in, torus_options());
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  ASSERT_EQ(encoded->report.fields.size(), c.fields.size());
  EXPECT_EQ(encoded->report.merged_points_with_other_values, 0u);
  EXPECT_EQ(encoded->bytes[8], 7);  // format 7.0: values and carving corrections

  ProgressiveDecoder dec;
  int levels = 0;
  ASSERT_TRUE(decode_stream(encoded->bytes, dec).ok());
  ProgressiveDecoder progressive;
  ASSERT_TRUE(
      progressive
          .feed(
              encoded->bytes,
              [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
                ++levels;
                ASSERT_EQ(d.fields().size(), c.fields.size());
                for (size_t f = 0; f < c.fields.size(); ++f) {
                  const FieldValues& got = d.fields()[f];
                  EXPECT_EQ(got.description.name, c.fields[f].name);
                  ASSERT_EQ(got.bits.size(), size_t{l.vertices} * c.fields[f].components);
                  const int k = c.fields[f].components;
                  for (size_t i = 0; i < c.mesh.points.size(); ++i) {
                    const uint32_t v = encoded->vertex_of_input[i];
                    if (v >= l.vertices) continue;
                    for (int j = 0; j < k; ++j)
                      ASSERT_EQ(got.bits[v * k + j], bits_of(c.fields[f].values[i * k + j], c.fields[f].type))
                          << c.fields[f].name << " point " << i << " level " << l.level;
                  }
                }
              })
          .ok());
  EXPECT_EQ(levels, dec.header().level_count);
  EXPECT_GT(levels, 1);
  // NaN's payload and -0's sign survive.
  const uint32_t v5 = encoded->vertex_of_input[5], v8 = encoded->vertex_of_input[8];
  EXPECT_TRUE(std::isnan(dec.fields()[1].value(v5, 0)));
  EXPECT_TRUE(std::signbit(dec.fields()[1].value(v8, 0)));
}

TEST(StreamValues, LossyFieldsStayWithinTheirBoundAtEveryLevel) {
  FieldCase c = torus_with_fields();
  c.values[1][5] = c.values[1][6] = c.values[1][7] = 0.5;  // a lossy field must be finite
  EncodeInput in;
  in.points = c.mesh.points;
  in.fields = c.fields;
  EncodeOptions o = torus_options();
  o.field_errors = {{"smooth", 1e-3}, {"velocity", 0.05}};
  const auto encoded = encode(in, o);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  EXPECT_TRUE(encoded->report.fields[1].description.lossy);
  ProgressiveDecoder dec;
  ASSERT_TRUE(
      dec.feed(encoded->bytes,
               [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
                 for (size_t f : {1, 2}) {
                   const int k = c.fields[f].components;
                   const double bound = f == 1 ? 1e-3 : 0.05;
                   for (size_t i = 0; i < c.mesh.points.size(); ++i) {
                     const uint32_t v = encoded->vertex_of_input[i];
                     if (v >= l.vertices) continue;
                     for (int j = 0; j < k; ++j)
                       ASSERT_LE(std::abs(d.fields()[f].value(v, j) - c.fields[f].values[i * k + j]), bound)
                           << c.fields[f].name << " point " << i;
                   }
                 }
               })
          .ok());
  // The lossy fields cost less than the same fields coded losslessly.
  EncodeInput exact = in;
  const auto lossless_encoded = encode(exact, torus_options());
  ASSERT_TRUE(lossless_encoded.ok());
  EXPECT_LT(encoded->report.fields[1].bytes, lossless_encoded->report.fields[1].bytes / 2);
}

TEST(StreamValues, FieldsThatCannotBeCodedAsAskedAreRefusedByName) {
  FieldCase c = torus_with_fields();
  EncodeInput in;
  in.points = c.mesh.points;
  in.fields = c.fields;
  auto refused = [&](const EncodeOptions& o, const std::string& says) {
    const auto r = encode(in, o);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.status().code(), StatusCode::kInvalidInput);
    EXPECT_NE(r.status().message().find(says), std::string::npos) << r.status().message();
  };
  EncodeOptions o = torus_options();
  o.field_errors = {{"smooth", 1e-3}};
  refused(o, "field 'smooth': point 5 holds NaN");
  o.field_errors = {{"label", 1}};
  refused(o, "only float fields can be lossy");
  o.field_errors = {{"nothing", 1}};
  refused(o, "'nothing', which is not a field");
  o.field_errors.clear();
  std::vector<double> short_values(10, 1.0);
  std::vector<EncodeInput::Field> wrong = {{"short", ValueType::kF64, 1, short_values}};
  in.fields = wrong;
  refused(o, "field 'short' has 10 values for 288 points");
}

// Any prefix of a stream with values decodes its whole layers with their
// values, and every damaged byte of the field table or a value section is
// refused (the checksums cover both).
TEST(StreamValues, PrefixesGiveWholeLayersWithTheirValuesAndDamageIsRefused) {
  FieldCase c = torus_with_fields();
  EncodeInput in;
  in.points = c.mesh.points;
  in.fields = std::span(c.fields).first(2);
  const auto encoded = encode(in, torus_options());
  ASSERT_TRUE(encoded.ok());
  const auto& bytes = encoded->bytes;
  for (size_t n = 0; n < bytes.size(); n += 7) {
    ProgressiveDecoder dec;
    ASSERT_TRUE(dec.feed(std::span(bytes).first(n)).ok()) << n;
    if (n > kHeaderSize + encoded->report.field_table_bytes) {
      ASSERT_EQ(dec.fields().size(), 2u);
    }
    for (const FieldValues& f : dec.fields())
      EXPECT_EQ(f.bits.size(), dec.points().size() * f.description.components);
  }
  // Flip one bit in every byte of the table and of the first layer's value section.
  const StreamSummary summary = scan_stream(bytes);
  ASSERT_TRUE(summary.status.ok());
  const auto& base = summary.layers.front();
  const size_t values_start = base.offset + base.size() - base.header.value_bytes;
  std::vector<size_t> targets;
  for (size_t i = kHeaderSize; i < kHeaderSize + summary.field_table_bytes; ++i) targets.push_back(i);
  for (size_t i = values_start; i < base.offset + base.size(); ++i) targets.push_back(i);
  for (size_t i : targets) {
    auto damaged = bytes;
    damaged[i] ^= 0x08;
    ProgressiveDecoder dec;
    const Status s = decode_stream(damaged, dec);
    EXPECT_FALSE(s.ok()) << "byte " << i;
    EXPECT_TRUE(dec.levels().empty()) << "byte " << i;
  }
}

// The decoder holds at most DecoderOptions::max_values values, checked
// before a layer's values are decoded; the levels before stand.
TEST(StreamValues, TheValueLimitIsEnforcedBeforeDecoding) {
  FieldCase c = torus_with_fields();
  EncodeInput in;
  in.points = c.mesh.points;
  in.fields = c.fields;  // 7 components
  const auto encoded = encode(in, torus_options());
  ASSERT_TRUE(encoded.ok());
  DecoderOptions options;
  options.max_values = 200 * 7;  // the base level fits, level 0 does not
  ProgressiveDecoder dec(options);
  const Status s = decode_stream(encoded->bytes, dec);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded) << s.message();
  ASSERT_FALSE(dec.levels().empty());
  EXPECT_LE(dec.points().size() * 7, options.max_values);
  EXPECT_EQ(dec.fields()[2].bits.size(), dec.points().size() * 3);
}

// The same limit where a bricked stream is read by box or piece (it used
// to hold only for level 0's cell data there).
TEST(StreamValues, TheValueLimitHoldsForARegionOfABrickedStream) {
  FieldCase c = torus_with_fields();
  EncodeInput in;
  in.points = c.mesh.points;
  in.tetrahedra = c.mesh.tets;
  in.fields = c.fields;  // 7 components
  EncodeOptions o = torus_options();
  o.bricks = true;
  const auto encoded = encode(in, o);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  const GridBox everything{{0, 0, 0}, {1 << 20, 1 << 20, 1 << 20}};
  DecoderOptions options;
  options.max_values = 200 * 7;  // the coarsest level fits, level 0 does not
  MemorySource source(encoded->bytes);
  const auto refused = decode_region(source, everything, 0, options);
  EXPECT_EQ(refused.status().code(), StatusCode::kLimitExceeded) << refused.status().message();
  EXPECT_EQ(decode_piece(source, 0, 0, 1, options).status().code(), StatusCode::kLimitExceeded);
  options.max_values = c.mesh.points.size() * 7;
  const auto whole = decode_region(source, everything, 0, options);
  ASSERT_TRUE(whole.ok()) << whole.status().message();
  EXPECT_EQ(whole->points.size(), c.mesh.points.size());
}

// Lossy fields on every corpus model: a smooth analytic field (a sum of
// Gaussians) in float32 and float64 within 1e-3 of its range, checked at
// every vertex of every level.
TEST(StreamValues, LossyBoundHoldsOnEveryCorpusModel) {
  for (const std::string& model : test::kCorpus) {
    const InputMesh mesh = read_input(test::data_path(model + ".node"));
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (const auto& p : mesh.points)
      for (int a = 0; a < 3; ++a) {
        const double x = a == 0 ? p.x : a == 1 ? p.y : p.z;
        lo[a] = std::min(lo[a], x), hi[a] = std::max(hi[a], x);
      }
    std::vector<double> field;
    double fmin = 1e300, fmax = -1e300;
    for (const auto& p : mesh.points) {
      double v = 0;
      for (int g = 0; g < 3; ++g) {
        const double cx = lo[0] + (hi[0] - lo[0]) * (0.3 + 0.2 * g),
                     cy = lo[1] + (hi[1] - lo[1]) * (0.6 - 0.1 * g);
        const double w = (hi[0] - lo[0]) * 0.3;
        v += std::exp(-((p.x - cx) * (p.x - cx) + (p.y - cy) * (p.y - cy)) / (w * w));
      }
      field.push_back(v);
      fmin = std::min(fmin, v), fmax = std::max(fmax, v);
    }
    std::vector<double> as_float(field.begin(), field.end());
    for (double& v : as_float) v = static_cast<float>(v);
    const std::vector<EncodeInput::Field> fields = {{"f32", ValueType::kF32, 1, as_float},
                                                    {"f64", ValueType::kF64, 1, field}};
    EncodeInput in;
    in.points = mesh.points;
    in.fields = fields;
    EncodeOptions o = EncodeOptions::paper();
    o.box = 256;
    o.dmax = 2;
    o.measure_boundary_error = false;
    const double e = 1e-3 * (fmax - fmin);
    o.field_errors = {{"f32", e}, {"f64", e}};
    const auto encoded = encode(in, o);
    ASSERT_TRUE(encoded.ok()) << model << ": " << encoded.status().message();
    // Points merged by quantization keep the first one's value.
    std::vector<uint8_t> first(mesh.points.size(), 0), taken(mesh.points.size(), 0);
    for (size_t i = 0; i < mesh.points.size(); ++i)
      if (!taken[encoded->vertex_of_input[i]]) taken[encoded->vertex_of_input[i]] = first[i] = 1;
    ProgressiveDecoder dec;
    int levels = 0;
    ASSERT_TRUE(dec.feed(encoded->bytes,
                         [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
                           ++levels;
                           for (size_t i = 0; i < mesh.points.size(); ++i) {
                             const uint32_t v = encoded->vertex_of_input[i];
                             if (v >= l.vertices || !first[i]) continue;
                             ASSERT_LE(std::abs(d.fields()[0].value(v, 0) - as_float[i]), e)
                                 << model << " point " << i;
                             ASSERT_LE(std::abs(d.fields()[1].value(v, 0) - field[i]), e)
                                 << model << " point " << i;
                           }
                         })
                    .ok());
    if (mesh.points.size() > 1000) {
      EXPECT_GT(levels, 1) << model;
    }
  }
}

}  // namespace
}  // namespace dtm
