// The binary range coder: what is encoded decodes, whatever the models say;
// a block is accepted only whole; raw bits cost exactly one bit each.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bitstream/range_coder.h"

namespace dtm {
namespace {

struct Symbol {
  bool raw;
  int model;      // adaptive: which model
  uint64_t value; // the bit, or the raw value
  int bits;       // raw: how many
};

std::vector<Symbol> random_symbols(uint32_t seed, size_t count) {
  std::mt19937 rng(seed);
  std::vector<Symbol> out;
  for (size_t i = 0; i < count; ++i) {
    Symbol s{};
    s.raw = rng() % 5 == 0;
    if (s.raw) {
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
    if (s.raw) enc.encode_raw(s.value, s.bits);
    else enc.encode(models[s.model], s.value != 0);
  }
  return enc.finish();
}

// Decodes and reports whether the decoder ended cleanly with every symbol right.
bool decodes_to(std::span<const uint8_t> block, const std::vector<Symbol>& symbols) {
  RangeDecoder dec(block);
  AdaptiveBit models[4];
  bool same = true;
  for (const Symbol& s : symbols) {
    const uint64_t v = s.raw ? dec.decode_raw(s.bits) : dec.decode(models[s.model]);
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
