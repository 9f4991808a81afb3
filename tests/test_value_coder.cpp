// The per-vertex value coder (codec/sections/value_coder.h): the order-preserving map
// of every value type, exact round trips layer by layer, what the gcd buys,
// and damaged sections refused.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "codec/sections/value_coder.h"
#include "test_support.h"

namespace dtm {
namespace {

uint64_t bits_of(float f) { return std::bit_cast<uint32_t>(f); }
uint64_t bits_of(double d) { return std::bit_cast<uint64_t>(d); }

TEST(ValueTypes, OrderedIntegersOrderAsTheFloatsAndComeBackBitForBit) {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> floats = {-inf,   -3.4e38f, -1.0f, -1e-40f, -0.0f, 0.0f,
                                     1e-45f, 1.0f,     2.5f,  3.4e38f, inf};
  for (size_t i = 0; i < floats.size(); ++i) {
    const Int128 o = to_ordered(bits_of(floats[i]), ValueType::kF32);
    EXPECT_EQ(from_ordered(o, ValueType::kF32), bits_of(floats[i])) << floats[i];
    if (i > 0) {
      EXPECT_LT(to_ordered(bits_of(floats[i - 1]), ValueType::kF32), o) << floats[i];
    }
  }
  const double dinf = std::numeric_limits<double>::infinity();
  const std::vector<double> doubles = {-dinf, -1e300, -1.0, -0.0, 0.0, 5e-324, 1.0, 1e300, dinf};
  for (size_t i = 0; i < doubles.size(); ++i) {
    const Int128 o = to_ordered(bits_of(doubles[i]), ValueType::kF64);
    EXPECT_EQ(from_ordered(o, ValueType::kF64), bits_of(doubles[i])) << doubles[i];
    if (i > 0) {
      EXPECT_LT(to_ordered(bits_of(doubles[i - 1]), ValueType::kF64), o) << doubles[i];
    }
  }
  // NaNs (any payload, either sign) survive bit for bit.
  for (const uint64_t nan : {uint64_t{0x7fc00001}, uint64_t{0xffc00000}})
    EXPECT_EQ(from_ordered(to_ordered(nan, ValueType::kF32), ValueType::kF32), nan);
  for (const uint64_t nan : {uint64_t{0x7ff8000000000001}, uint64_t{0xfff0000000000001}})
    EXPECT_EQ(from_ordered(to_ordered(nan, ValueType::kF64), ValueType::kF64), nan);
  // Integers are themselves; their extremes come back.
  EXPECT_EQ(to_ordered(0xff, ValueType::kI8), -1);
  EXPECT_EQ(to_ordered(0xff, ValueType::kU8), 255);
  EXPECT_EQ(from_ordered(to_ordered(0x8000000000000000, ValueType::kI64), ValueType::kI64),
            0x8000000000000000);
  EXPECT_EQ(from_ordered(to_ordered(~uint64_t{0}, ValueType::kU64), ValueType::kU64), ~uint64_t{0});
}

// Points in three layers (coarsest first, as a decoder produces them) with a
// smooth field plus noise, as ordered integers of `type`.
struct Layers {
  std::vector<std::vector<GridPoint>> points;
  std::vector<std::vector<Int128>> values;
};

Layers smooth_field(ValueType type, uint32_t seed) {
  const std::vector<GridPoint> all = test::random_grid_points(3000, 10, seed);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 2);
  Layers l;
  const size_t cuts[] = {0, 300, 1200, all.size()};
  for (int k = 0; k < 3; ++k) {
    l.points.emplace_back(all.begin() + cuts[k], all.begin() + cuts[k + 1]);
    std::vector<Int128> v;
    for (const GridPoint& p : l.points.back()) {
      const double f = 1000 * std::sin(p.x / 400.0) * std::cos(p.y / 500.0) + p.z / 3.0 + noise(rng);
      uint64_t bits = 0;
      if (type == ValueType::kF32)
        bits = bits_of(static_cast<float>(f));
      else if (type == ValueType::kF64)
        bits = bits_of(f);
      else if (type == ValueType::kU16)
        bits = static_cast<uint16_t>(std::lround(f + 2000));
      else
        bits = static_cast<uint64_t>(static_cast<int64_t>(std::lround(f)));
      v.push_back(to_ordered(bits, type));
    }
    l.values.push_back(std::move(v));
  }
  return l;
}

size_t round_trip(const Layers& l, std::vector<std::vector<uint8_t>>* sections = nullptr) {
  std::vector<Int128> every;
  for (const auto& v : l.values) every.insert(every.end(), v.begin(), v.end());
  const ValueScale scale = value_scale(every);
  ValueEncoder enc(scale);
  ValueDecoder dec(scale);
  size_t bytes = 0;
  for (size_t k = 0; k < l.points.size(); ++k) {
    const std::vector<uint8_t> section = enc.encode_layer(l.points[k], l.values[k]);
    bytes += section.size();
    if (sections) sections->push_back(section);
    std::vector<Int128> decoded;
    EXPECT_TRUE(dec.decode_layer(section, l.points[k], decoded).ok()) << "layer " << k;
    EXPECT_TRUE(decoded == l.values[k]) << "layer " << k;
  }
  return bytes;
}

TEST(ValueCoder, EveryTypeComesBackExactlyLayerByLayer) {
  for (const ValueType type : {ValueType::kI32, ValueType::kU16, ValueType::kF32, ValueType::kF64}) {
    SCOPED_TRACE(static_cast<int>(type));
    round_trip(smooth_field(type, 5));
  }
  // The extremes of a 64-bit type: residuals of 65 bits.
  Layers wide;
  wide.points = {{{0, 0, 0}, {100, 0, 0}}, {{50, 0, 0}, {25, 0, 0}, {75, 3, 0}}};
  wide.values = {{to_ordered(0, ValueType::kU64), to_ordered(~uint64_t{0}, ValueType::kU64)},
                 {to_ordered(1, ValueType::kU64), to_ordered(~uint64_t{1}, ValueType::kU64), 12345}};
  round_trip(wide);
}

TEST(ValueCoder, PredictionFromTheCoarserLevelsBeatsTheValuesAlone) {
  // A smooth field sampled by scattered points costs at least 2 bits per
  // value less than a uniform code over its range (log2 of about 2400).
  const Layers l = smooth_field(ValueType::kI32, 9);
  Int128 lo = l.values[0][0], hi = lo;
  for (const auto& v : l.values)
    for (const Int128 x : v) lo = std::min(lo, x), hi = std::max(hi, x);
  const double uniform = std::log2(static_cast<double>(hi - lo + 1));
  const size_t bytes = round_trip(l);
  EXPECT_LT(8.0 * static_cast<double>(bytes) / 3000, uniform - 2) << "uniform " << uniform;
}

TEST(ValueCoder, ValuesOnAStepCostWhatTheirQuotientCosts) {
  // CT numbers in steps of 10: the gcd takes log2(10) bits off each value.
  Layers l = smooth_field(ValueType::kI32, 3);
  const size_t plain = round_trip(l);
  for (auto& v : l.values)
    for (Int128& x : v) x *= 10;
  std::vector<Int128> every;
  for (const auto& v : l.values) every.insert(every.end(), v.begin(), v.end());
  EXPECT_EQ(value_scale(every).step % 10, 0);
  EXPECT_EQ(round_trip(l), plain);
}

TEST(ValueCoder, ADamagedSectionIsRefusedNotMisread) {
  const Layers l = smooth_field(ValueType::kI32, 7);
  std::vector<std::vector<uint8_t>> sections;
  round_trip(l, &sections);
  std::vector<Int128> every;
  for (const auto& v : l.values) every.insert(every.end(), v.begin(), v.end());
  const ValueScale scale = value_scale(every);
  // Every truncation of the first layer's section, and one byte too many.
  const std::vector<uint8_t>& s = sections[0];
  for (size_t cut = 0; cut < s.size(); ++cut) {
    ValueDecoder dec(scale);
    std::vector<Int128> out;
    EXPECT_FALSE(dec.decode_layer(std::span(s).first(cut), l.points[0], out).ok()) << cut;
  }
  std::vector<uint8_t> longer = s;
  longer.push_back(0);
  ValueDecoder dec(scale);
  std::vector<Int128> out;
  EXPECT_FALSE(dec.decode_layer(longer, l.points[0], out).ok());
  // Flipped bits: refused, or decoded to a value for every point (the
  // section has no checksum of its own: its layer's covers it), never a
  // crash.
  ValueDecoder plain(scale);
  std::vector<Int128> undamaged;
  ASSERT_TRUE(plain.decode_layer(s, l.points[0], undamaged).ok());
  size_t refused = 0;
  for (size_t bit = 0; bit < 8 * s.size(); bit += 7) {
    std::vector<uint8_t> flipped = s;
    flipped[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
    ValueDecoder d(scale);
    std::vector<Int128> o;
    if (!d.decode_layer(flipped, l.points[0], o).ok()) {
      ++refused;
      continue;
    }
    EXPECT_EQ(o.size(), undamaged.size()) << "bit " << bit;
  }
  EXPECT_GT(refused, 0u) << "some flips are found out by the section itself";
}

TEST(LossyValues, EveryDecodedValueIsWithinTheBoundInItsOwnType) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1e4, 1e4);
  std::vector<double> values(5000);
  for (double& v : values) v = u(rng);
  values[7] = 1e-30;  // tiny next to the range
  for (const bool float32 : {false, true}) {
    if (float32)
      for (double& v : values) v = static_cast<float>(v);
    // (float32 holds values near 1e4 to about 1e-3: a bound must exceed that.)
    for (const double error : {float32 ? 0.01 : 1e-3, 0.5, 7.0}) {
      LossyScale scale;
      const auto q = quantize_within(values, error, float32, scale);
      ASSERT_TRUE(q.ok()) << q.status().message();
      for (size_t i = 0; i < values.size(); ++i)
        ASSERT_LE(std::abs(dequantize((*q)[i], scale, float32) - values[i]), error) << i << " " << error;
    }
  }
}

TEST(LossyValues, NaNInfinityAndHopelessBoundsAreRefusedNamingTheVertex) {
  LossyScale scale;
  std::vector<double> v = {1, 2, std::nan(""), 4};
  auto q = quantize_within(v, 0.1, false, scale);
  ASSERT_FALSE(q.ok());
  EXPECT_NE(q.status().message().find("vertex 2"), std::string::npos) << q.status().message();
  v[2] = -std::numeric_limits<double>::infinity();
  EXPECT_FALSE(quantize_within(v, 0.1, false, scale).ok());
  // A bound under the values' own precision.
  EXPECT_FALSE(quantize_within(std::vector<double>{1e15, 1e15 + 0.25, 0}, 1e-6, false, scale).ok());
  EXPECT_FALSE(quantize_within(std::vector<double>{1, 2}, 0, false, scale).ok());
}

}  // namespace
}  // namespace dtm
