// The binary range coder: what is encoded decodes, whatever the models say;
// a block is accepted only whole; raw bits cost exactly one bit each, uniform
// symbols log2(count) bits.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bitstream/range_coder.h"

namespace dtm {
namespace {

struct Symbol {
  bool raw;
  int model;       // adaptive: which model
  uint64_t value;  // the bit, the raw value or the uniform one
  int bits;        // raw: how many
  uint32_t count;  // > 0: a uniform symbol in [0, count)
};

std::vector<Symbol> random_symbols(uint32_t seed, size_t count) {
  std::mt19937 rng(seed);
  std::vector<Symbol> out;
  for (size_t i = 0; i < count; ++i) {
    Symbol s{};
    s.raw = rng() % 5 == 0;
    if (!s.raw && rng() % 4 == 0) {
      s.count = 2 + rng() % (kMaxUniform - 1);
      if (rng() % 2) s.count = 2 + s.count % 7;  // small counts too
      s.value = rng() % s.count;
    } else if (s.raw) {
      s.bits = static_cast<int>(rng() % 65);
      s.value = s.bits == 0 ? 0 : (uint64_t{rng()} << 32 | rng()) >> (64 - s.bits);
    } else {
      s.model = static_cast<int>(rng() % 4);
      // Model m emits ones with probability m / 4 + 1/8: skewed and balanced streams.
      s.value = (rng() % 8) < static_cast<uint32_t>(2 * s.model + 1);
    }
    out.push_back(s);
  }
  return out;
}

std::vector<uint8_t> encode(const std::vector<Symbol>& symbols) {
  RangeEncoder enc;
  AdaptiveBit models[4];
  for (const Symbol& s : symbols) {
    if (s.count > 0)
      enc.encode_uniform(static_cast<uint32_t>(s.value), s.count);
    else if (s.raw)
      enc.encode_raw(s.value, s.bits);
    else
      enc.encode(models[s.model], s.value != 0);
  }
  return enc.finish();
}

// Decodes and reports whether the decoder ended cleanly with every symbol right.
bool decodes_to(std::span<const uint8_t> block, const std::vector<Symbol>& symbols) {
  RangeDecoder dec(block);
  AdaptiveBit models[4];
  bool same = true;
  for (const Symbol& s : symbols) {
    uint32_t uniform = UINT32_MAX;
    if (s.count > 0 && !dec.decode_uniform(s.count, uniform).ok()) return false;
    const uint64_t v = s.count > 0 ? uniform : s.raw ? dec.decode_raw(s.bits) : dec.decode(models[s.model]);
    same = same && v == s.value;
  }
  return same && dec.finished_cleanly();
}

TEST(RangeCoder, RoundTripsMixedAdaptiveAndRawSymbols) {
  for (uint32_t seed = 1; seed <= 30; ++seed) {
    const auto symbols = random_symbols(seed, 1 + seed * 97);
    const auto block = encode(symbols);
    EXPECT_TRUE(decodes_to(block, symbols)) << "seed " << seed;
  }
}

TEST(RangeCoder, OnlyTheWholeBlockIsAccepted) {
  const auto symbols = random_symbols(77, 500);
  const auto block = encode(symbols);
  for (size_t cut = 0; cut < block.size(); ++cut)
    EXPECT_FALSE(decodes_to(std::span(block).first(cut), symbols)) << "cut at " << cut;
  auto longer = block;
  longer.push_back(0);
  EXPECT_FALSE(decodes_to(longer, symbols));
}

TEST(RangeCoder, RawBitsCostOneBitEach) {
  RangeEncoder enc;
  for (int i = 0; i < 1000; ++i) enc.encode_raw(0x5A5A5A5A5A5A5A5Aull * (i + 1), 64);
  const size_t bytes = enc.finish().size();
  EXPECT_GE(bytes, 8000u);
  EXPECT_LE(bytes, 8000u + 5);  // the final flush
}

TEST(RangeCoder, UniformSymbolsCostLog2OfTheirCount) {
  for (uint32_t count : {3u, 1000u, kMaxUniform}) {
    std::mt19937 rng(count);
    RangeEncoder enc;
    const int n = 20000;
    for (int i = 0; i < n; ++i) enc.encode_uniform(rng() % count, count);
    const double bits = 8.0 * enc.finish().size(), ideal = n * std::log2(count);
    EXPECT_LT(bits, ideal * 1.002 + 40) << count;
    EXPECT_GT(bits, ideal * 0.998) << count;
  }
}

// Damaged bytes: a uniform symbol either decodes into its range or is
// refused, never a value past it, and the decoder stays usable after.
TEST(RangeCoder, UniformSymbolsFromJunkStayInRangeOrSaySo) {
  // The code past the last whole multiple of range / count: 0xFFFFFFFF with
  // range 2^32 - 1 and count 3 is no symbol.
  const std::vector<uint8_t> past_the_end = {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
  RangeDecoder dec(past_the_end);
  uint32_t v = 0;
  EXPECT_EQ(dec.decode_uniform(3, v).code(), StatusCode::kCorrupt);
  const Status after = dec.decode_uniform(kMaxUniform, v);
  EXPECT_TRUE(!after.ok() || v < kMaxUniform);
  std::mt19937 rng(4);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<uint8_t> junk(8);
    for (auto& b : junk) b = static_cast<uint8_t>(rng());
    RangeDecoder d(junk);
    for (int i = 0; i < 6; ++i) {
      const uint32_t count = 2 + rng() % 300;
      uint32_t value = count;
      const Status s = d.decode_uniform(count, value);
      ASSERT_TRUE(s.ok() ? value < count : s.code() == StatusCode::kCorrupt);
    }
  }
}

TEST(RangeCoder, AdaptiveBitsApproachTheEntropy) {
  // 100k bits with P(1) = 0.05: entropy 0.2864 bits each.
  std::mt19937 rng(3);
  RangeEncoder enc;
  AdaptiveBit model;
  const int n = 100000;
  for (int i = 0; i < n; ++i) enc.encode(model, rng() % 100 < 5);
  const double bits = 8.0 * enc.finish().size();
  const double entropy = n * (-(0.05 * std::log2(0.05) + 0.95 * std::log2(0.95)));
  EXPECT_LT(bits, entropy * 1.03) << bits << " vs " << entropy;
  EXPECT_GT(bits, entropy * 0.97);
}

}  // namespace
}  // namespace dtm
