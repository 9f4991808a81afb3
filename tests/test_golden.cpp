// Golden streams (spec/FORMAT.md §6): streams of format 4.0 (with carving
// corrections, and the paper's alpha carving), and of 3.0 and 2.0
// (golden/v3/, golden/v2/, which this decoder still reads), that every later decoder must
// decode to the same levels, and whose every damaged variant it must refuse.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "codec/decode.h"
#include "codec/format.h"

namespace dtm {
namespace {

std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string golden(const std::string& name) { return std::string(DTM_TEST_SOURCE_DIR) + "/golden/" + name; }

std::string hex(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

class GoldenStream : public ::testing::TestWithParam<std::string> {};

TEST_P(GoldenStream, DecodesToTheRecordedLevels) {
  const auto bytes = read_bytes(golden(GetParam() + ".dtm"));
  ASSERT_FALSE(bytes.empty());
  std::ifstream expected_file(golden(GetParam() + ".expected.json"));
  const auto expected = nlohmann::json::parse(expected_file);
  size_t index = 0;
  ProgressiveDecoder dec;
  ASSERT_TRUE(dec.feed(bytes,
                       [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
                         ASSERT_LT(index, expected["levels"].size());
                         const auto& want = expected["levels"][index++];
                         EXPECT_EQ(l.level, want["level"].get<int>());
                         EXPECT_EQ(l.vertices, want["vertices"].get<uint32_t>());
                         EXPECT_EQ(hex(cell_set_hash(d.points(), d.carved_cells())),
                                   want["cell_hash"].get<std::string>())
                             << GetParam() << " level " << l.level;
                       })
                  .ok());
  EXPECT_TRUE(dec.finish().ok());
  EXPECT_EQ(index, expected["levels"].size());
  EXPECT_EQ(dec.header().grid.qbits, expected["qbits"].get<int>());
  EXPECT_EQ(dec.header().vertex_count, expected["vertices"].get<uint32_t>());
}

// Every byte is under a checksum, so any single flipped bit must be refused;
// a decoder may stop early but must never return a wrong level as valid.
TEST_P(GoldenStream, EverySingleBitFlipIsRefused) {
  const auto bytes = read_bytes(golden(GetParam() + ".dtm"));
  for (size_t i = 0; i < bytes.size(); ++i)
    for (int b = 0; b < 8; ++b) {
      auto damaged = bytes;
      damaged[i] ^= static_cast<uint8_t>(1 << b);
      ProgressiveDecoder dec;
      const Status s = dec.feed(damaged);
      ASSERT_FALSE(s.ok() && dec.finish().ok()) << "flip of bit " << b << " of byte " << i;
      EXPECT_FALSE(scan_stream(damaged).status.ok());
    }
}

INSTANTIATE_TEST_SUITE_P(Format4_0, GoldenStream,
                         ::testing::Values("torus_288", "torus_288_paper", "torus_288_grid_q10_hull",
                                           "torus_288_q24"));
INSTANTIATE_TEST_SUITE_P(Format3_0, GoldenStream,
                         ::testing::Values("v3/torus_288", "v3/torus_288_grid_q10_hull", "v3/torus_288_q24"));
INSTANTIATE_TEST_SUITE_P(Format2_0, GoldenStream,
                         ::testing::Values("v2/torus_288", "v2/torus_288_grid_q10_hull", "v2/torus_288_q24"));

}  // namespace
}  // namespace dtm
