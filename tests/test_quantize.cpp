#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/grid.h"
#include "core/quantize.h"

namespace dtm {
namespace {

TEST(Quantize, DracoStyleGridOverTheBoundingCube) {
  const std::vector<InputPoint> in = {{1, 2, 3}, {5, 2, 3}, {1, 4.1, 4}};
  const auto q = quantize(in, 3).value();
  EXPECT_EQ(q.grid.origin, (std::array<double, 3>{1, 2, 3}));
  EXPECT_DOUBLE_EQ(q.grid.step, 4.0 / 7);  // largest extent / (2^q - 1)
  ASSERT_EQ(q.points.size(), 3u);
  // Points are sorted; the largest extent spans the whole grid.
  EXPECT_EQ(q.points[0], (GridPoint{0, 0, 0}));
  EXPECT_EQ(q.points[1], (GridPoint{0, 4, 2}));  // 2.1 / (4/7) = 3.675 -> 4; 1 / (4/7) = 1.75 -> 2
  EXPECT_EQ(q.points[2], (GridPoint{7, 0, 0}));
  EXPECT_EQ(q.input_to_point, (std::vector<uint32_t>{0, 2, 1}));
}

// The encoder's --box scales while quantizing (no scaled copy of 10M
// points): the same grid as quantizing the scaled points.
TEST(Quantize, ScalingWhileQuantizingEqualsQuantizingAScaledCopy) {
  std::vector<InputPoint> in;
  for (int i = 0; i < 2000; ++i) in.push_back({std::sin(i) * 3.3, std::cos(i * 1.7) * 0.2, i * 0.0013});
  for (const double scale : {1.0, 0.37, 1234.5}) {
    std::vector<InputPoint> scaled = in;
    for (auto& p : scaled) p = {p.x * scale, p.y * scale, p.z * scale};
    const auto want = quantize(scaled, 12).value();
    const auto got = quantize(in, 12, scale).value();
    EXPECT_EQ(got.points, want.points) << scale;
    EXPECT_EQ(got.input_to_point, want.input_to_point) << scale;
    EXPECT_EQ(got.grid.origin, want.grid.origin) << scale;
    EXPECT_EQ(got.grid.step, want.grid.step) << scale;
    EXPECT_EQ(got.duplicates_merged, want.duplicates_merged) << scale;
  }
}

TEST(Quantize, DuplicatesAreMergedAndCounted) {
  const std::vector<InputPoint> in = {{0, 0, 0}, {1, 1, 1}, {0.0001, 0, 0}, {1, 1, 1}, {0.5, 0, 0}};
  const auto q = quantize(in, 4).value();
  EXPECT_EQ(q.duplicates_merged, 2u);
  EXPECT_EQ(q.points.size(), 3u);
  EXPECT_EQ(q.input_to_point[0], q.input_to_point[2]);
  EXPECT_EQ(q.input_to_point[1], q.input_to_point[3]);
  EXPECT_NE(q.input_to_point[0], q.input_to_point[4]);
}

// The grid points are the input's cells, distinct and ascending, each one
// some input point's, and each input point names its own cell: with most
// points merged, in an order the sort must undo.
TEST(Quantize, PointsAreTheDistinctCellsAscendingEachInputNamingItsOwn) {
  std::vector<InputPoint> in;
  for (int i = 0; i < 20000; ++i)
    in.push_back({std::sin(i * 7.1) * 3, std::cos(i * 1.3), (i * 37 % 1000) * 0.001});
  for (int bits : {3, 6, 14}) {
    const auto q = quantize(in, bits).value();
    EXPECT_EQ(q.points.size() + q.duplicates_merged, in.size());
    if (bits == 3) {
      EXPECT_GT(q.duplicates_merged, in.size() / 2);
    }
    for (size_t k = 1; k < q.points.size(); ++k) ASSERT_LT(q.points[k - 1], q.points[k]) << k;
    std::vector<uint8_t> named(q.points.size(), 0);
    ASSERT_EQ(q.input_to_point.size(), in.size());
    for (size_t i = 0; i < in.size(); ++i) {
      const uint32_t p = q.input_to_point[i];
      ASSERT_LT(p, q.points.size());
      named[p] = 1;
      const InputPoint back = q.grid.to_input(q.points[p]);
      EXPECT_LE(std::abs(back.x - in[i].x), q.grid.step * 0.5 + 1e-12) << i;
      EXPECT_LE(std::abs(back.y - in[i].y), q.grid.step * 0.5 + 1e-12) << i;
      EXPECT_LE(std::abs(back.z - in[i].z), q.grid.step * 0.5 + 1e-12) << i;
    }
    EXPECT_EQ(std::count(named.begin(), named.end(), 0), 0);
  }
}

TEST(Quantize, RoundTripErrorIsHalfAStep) {
  std::vector<InputPoint> in;
  for (int i = 0; i < 1000; ++i) in.push_back({std::sin(i) * 3, std::cos(i * 1.3), i * 0.001});
  for (int bits : {1, 8, 14, 24}) {
    const auto q = quantize(in, bits).value();
    for (size_t i = 0; i < in.size(); ++i) {
      const InputPoint back = q.grid.to_input(q.points[q.input_to_point[i]]);
      EXPECT_LE(std::abs(back.x - in[i].x), q.grid.step * 0.5 + 1e-12);
      EXPECT_LE(std::abs(back.y - in[i].y), q.grid.step * 0.5 + 1e-12);
      EXPECT_LE(std::abs(back.z - in[i].z), q.grid.step * 0.5 + 1e-12);
    }
  }
}

TEST(Quantize, RejectsBadInput) {
  const std::vector<InputPoint> ok = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_EQ(quantize(ok, 0).status().code(), StatusCode::kInvalidInput);
  EXPECT_EQ(quantize(ok, 25).status().code(), StatusCode::kInvalidInput);
  EXPECT_EQ(quantize({}, 14).status().code(), StatusCode::kInvalidInput);
  const std::vector<InputPoint> nan = {{0, 0, 0}, {std::numeric_limits<double>::quiet_NaN(), 0, 0}};
  EXPECT_EQ(quantize(nan, 14).status().code(), StatusCode::kInvalidInput);
}

}  // namespace
}  // namespace dtm
