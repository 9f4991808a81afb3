// The one-call encoder (codec/encode.h): it is the expert path composed,
// it says where each input point's vertex comes out of the decoder, and it
// refuses what cannot make a mesh with a Status, not an exception.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <tuple>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/expert_encode.h"
#include "mesh/delaunay.h"
#include "test_support.h"
#include "tools/formats/input.h"

namespace dtm {
namespace {

InputMesh torus() { return read_input(test::data_path("torus_288.node")); }

TEST(EncodeApi, IsQuantizeThenBuildThenEncodeStream) {
  const InputMesh in = torus();
  EncodeInput input;
  input.points = in.points;
  EncodeOptions options;
  options.scale = 25;
  options.dmax = 3;
  options.cell_hashes = true;
  const auto encoded = encode(input, options);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();

  std::vector<InputPoint> scaled = in.points;
  for (auto& p : scaled) p = {p.x * 25, p.y * 25, p.z * 25};
  const QuantizedPoints q = quantize(scaled, 14).value();
  HierarchyOptions h;
  h.dmax = 3 / q.grid.step;
  h.carve_to_reference = options.carve_to_reference;
  h.removal_share = options.removal_share;
  h.quality_ratio = options.quality_ratio;
  h.average_quality_floor = options.average_quality_floor;
  const Hierarchy hierarchy = build_hierarchy(q.points, h).value();
  StreamOptions s;
  s.cell_hashes = true;
  // The stream holds the grid in the input's units (the scale measures).
  Grid stream_grid = q.grid;
  for (double& o : stream_grid.origin) o /= 25;
  stream_grid.step /= 25;
  const EncodedStream expert = encode_stream(hierarchy, q.points, stream_grid, AlphaKind::kPaper, s).value();
  EXPECT_EQ(encoded->bytes, expert.bytes);
  EXPECT_EQ(encoded->report.levels.size(), hierarchy.levels.size());
  EXPECT_EQ(encoded->report.stream_bytes, expert.bytes.size());
}

// What per-vertex values will rely on: input point i comes out of the
// decoder as vertex vertex_of_input[i], at its quantized position.
TEST(EncodeApi, SaysWhereTheDecoderPutsEachInputPoint) {
  InputMesh in = torus();
  in.points.push_back(in.points[7]);  // a duplicate shares its vertex
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  EncodeOptions options;
  options.box = 256;
  options.dmax = 2;
  options.level_step = 2;
  const auto encoded = encode(input, options);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  ASSERT_EQ(encoded->vertex_of_input.size(), in.points.size());
  EXPECT_EQ(encoded->vertex_of_input.back(), encoded->vertex_of_input[7]);
  EXPECT_EQ(encoded->report.duplicates_merged, 1u);
  EXPECT_GT(encoded->report.reference_tetrahedra, 0u);
  ProgressiveDecoder decoder;
  ASSERT_TRUE(decode_stream(encoded->bytes, decoder).ok());
  // The box sets the units the encoder measures in, not the stream's: the
  // header's grid is the report's divided by the scale, and every point
  // decodes within half a step of its own input position.
  const Grid& grid = decoder.header().grid;
  const double scale = encoded->report.scale;
  ASSERT_GT(scale, 10.0);
  EXPECT_NEAR(grid.step * scale, encoded->report.grid.step, 1e-12 * encoded->report.grid.step);
  const double half = grid.step * 0.5 * (1 + 1e-9);
  for (size_t i = 0; i < in.points.size(); ++i) {
    const InputPoint p = grid.to_input(decoder.points().at(encoded->vertex_of_input[i]));
    EXPECT_LE(std::abs(p.x - in.points[i].x), half) << i;
    EXPECT_LE(std::abs(p.y - in.points[i].y), half) << i;
    EXPECT_LE(std::abs(p.z - in.points[i].z), half) << i;
  }
  for (const LevelReport& level : encoded->report.levels) EXPECT_TRUE(level.reference_error.has_value());
}

TEST(EncodeApi, RefusesWhatCannotMakeAMeshWithAStatus) {
  EncodeInput input;
  const std::vector<InputPoint> three = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  input.points = three;
  EXPECT_EQ(encode(input).status().code(), StatusCode::kInvalidInput);
  const std::vector<InputPoint> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 3, 0}};
  input.points = flat;
  EXPECT_EQ(encode(input).status().code(), StatusCode::kInvalidInput);
  const InputMesh in = torus();
  input.points = in.points;
  EncodeOptions options;
  options.qbits = 25;
  EXPECT_EQ(encode(input, options).status().code(), StatusCode::kInvalidInput);
  options = {};
  options.alpha = AlphaKind::kFixed;  // without its value
  EXPECT_EQ(encode(input, options).status().code(), StatusCode::kInvalidInput);
  const std::vector<std::array<uint32_t, 4>> beyond = {{0, 1, 2, 9999}};
  input.tetrahedra = beyond;
  EXPECT_EQ(encode(input).status().code(), StatusCode::kInvalidInput);
}

// A field's values as doubles, each rounded to the field's type: one the
// type cannot hold (300 as a uint8, NaN as an int16, 1e300 as a float32) is
// refused, naming the field and the point, where it was stored as 0; a
// value between two integers is rounded to the nearer, not truncated; a
// type that is none is refused, not written into a stream the decoder
// refuses. Cell data alike.
TEST(EncodeApi, RefusesAFieldValueItsTypeCannotHoldAndRoundsTheOthers) {
  const InputMesh in = torus();
  const size_t n = in.points.size();
  const auto encoded = [&](ValueType type, std::vector<double> values, size_t at = 0) {
    std::vector<double> all(n, 7);
    for (size_t i = 0; i < values.size(); ++i) all[at + i] = values[i];
    const std::vector<EncodeInput::Field> fields = {{"f", type, 1, all}};
    EncodeInput input;
    input.points = in.points;
    input.tetrahedra = in.tets;
    input.fields = fields;
    return encode(input);
  };
  for (const auto& [type, value] :
       std::vector<std::pair<ValueType, double>>{{ValueType::kU8, 300},
                                                 {ValueType::kU8, -1},
                                                 {ValueType::kI32, 1e12},
                                                 {ValueType::kI16, NAN},
                                                 {ValueType::kI64, INFINITY},
                                                 {ValueType::kU64, 0x1p64},
                                                 {ValueType::kI64, 0x1p63},
                                                 {ValueType::kI64, 0x1p53 + 2},
                                                 {ValueType::kU64, 0x1p62},
                                                 {ValueType::kF32, 1e300},
                                                 {ValueType::kF32, 0x1.fffffep127 + 0x1p103}}) {
    const auto out = encoded(type, {value}, 5);
    SCOPED_TRACE(std::string(value_type_name(type)) + " " + std::to_string(value));
    ASSERT_EQ(out.status().code(), StatusCode::kInvalidInput);
    EXPECT_NE(out.status().message().find("field 'f': point 5 holds"), std::string::npos)
        << out.status().message();
  }
  EXPECT_EQ(encoded(static_cast<ValueType>(77), {}).status().code(), StatusCode::kInvalidInput);
  // In range: 1.5 and 2.5 rounded away from zero, -0.4 to 0; a float32's NaN
  // kept; a 64-bit integer up to 2^53 (beyond, a double may hold another one).
  for (const auto& [type, values, expected] :
       std::vector<std::tuple<ValueType, std::vector<double>, std::vector<double>>>{
           {ValueType::kI32, {1.5, 2.5, -0.4, -2.6}, {2, 3, 0, -3}},
           {ValueType::kU8, {254.6, 0.2}, {255, 0}},
           {ValueType::kI64, {0x1p53, -0x1p53}, {0x1p53, -0x1p53}},
           {ValueType::kF32,
            {NAN, INFINITY, 0.1, 3.4028235e+38},
            {NAN, INFINITY, static_cast<float>(0.1), std::numeric_limits<float>::max()}}}) {
    const auto out = encoded(type, values);
    ASSERT_TRUE(out.ok()) << out.status().message();
    ProgressiveDecoder dec;
    ASSERT_TRUE(decode_stream(out->bytes, dec).ok());
    const auto& where = out->vertex_of_input;
    for (size_t i = 0; i < values.size(); ++i) {
      const double got = dec.fields()[0].value(where[i], 0);
      if (std::isnan(expected[i]))
        EXPECT_TRUE(std::isnan(got)) << i;
      else
        EXPECT_EQ(got, expected[i]) << i;
    }
  }
  // Cell data: a cell's value its type cannot hold.
  std::vector<double> cells(in.tets.size(), 1);
  cells[3] = 70000;
  const std::vector<EncodeInput::Field> cell_fields = {{"zone", ValueType::kU16, 1, cells}};
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.cell_fields = cell_fields;
  const auto out = encode(input);
  ASSERT_EQ(out.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(out.status().message().find("field 'zone': cell 3 holds 70000, which is not a uint16 value"),
            std::string::npos)
      << out.status().message();
}

// A caller short of memory frees its points, values and tetrahedra when the
// encoder says it reads them no more (meshenc does at 10M vertices): the
// stream is the one made without freeing, and a later read of what was freed
// is the sanitized build's failure.
TEST(EncodeApi, TheCallerMayFreeItsInputWhenTheEncoderIsDoneWithIt) {
  const InputMesh torus_mesh = torus();
  std::vector<double> marks(torus_mesh.points.size());
  for (size_t i = 0; i < marks.size(); ++i) marks[i] = static_cast<double>(i % 7);
  for (const bool bricks : {false, true}) {
    EncodeOptions options;
    options.scale = 25;
    options.dmax = 3;
    options.bricks = bricks;
    options.brick_points = 16;
    options.block_points = 100;
    const std::vector<EncodeInput::Field> kept_fields = {{"marks", ValueType::kF64, 1, marks}};
    EncodeInput kept;
    kept.points = torus_mesh.points;
    kept.tetrahedra = torus_mesh.tets;
    kept.fields = kept_fields;
    const StatusOr<EncodedMesh> expected = encode(kept, options);
    ASSERT_TRUE(expected.ok()) << expected.status().message();

    std::vector<InputPoint> points = torus_mesh.points;
    std::vector<std::array<uint32_t, 4>> tets = torus_mesh.tets;
    std::vector<double> values = marks;
    std::vector<EncodeInput::Field> fields = {{"marks", ValueType::kF64, 1, values}};
    EncodeInput freed;
    freed.points = points;
    freed.tetrahedra = tets;
    freed.fields = fields;
    bool points_freed = false, tets_freed = false;
    freed.points_done = [&] {
      freed.points = {};
      freed.fields = {};
      std::vector<InputPoint>().swap(points);
      std::vector<double>().swap(values);
      points_freed = true;
    };
    freed.tetrahedra_done = [&] {
      freed.tetrahedra = {};
      std::vector<std::array<uint32_t, 4>>().swap(tets);
      tets_freed = true;
    };
    const StatusOr<EncodedMesh> got = encode(freed, options);
    ASSERT_TRUE(got.ok()) << got.status().message();
    EXPECT_TRUE(points_freed);
    EXPECT_EQ(tets_freed, bricks);  // the whole-level encoder reads them to the end
    EXPECT_EQ(got->bytes, expected->bytes) << (bricks ? "bricked" : "whole levels");
  }
}

}  // namespace
}  // namespace dtm

namespace dtm {
namespace {

// Large batches are tetrahedralized on every core, and the threads leave the
// cells in an order of their own; nothing the encoder decides may depend on
// it (a triangulation is exported in the canonical cell order:
// DelaunayUniqueness.ExportIsInTheCanonicalOrder). 60,000 points, their
// reference solid a torus of their Delaunay cells (most points outside it):
// the parallel paths, the check and the repairs all run.
TEST(EncodeApi, TheSameInputGivesTheSameStreamEveryTime) {
  const std::vector<GridPoint> grid = test::random_grid_points(60000, 10, 17);
  std::vector<InputPoint> points;
  for (const GridPoint& p : grid) points.push_back({double(p.x), double(p.y), double(p.z)});
  std::vector<std::array<uint32_t, 4>> torus;
  const TetMesh dt = delaunay_tetrahedralize(grid).value();
  for (const auto& c : dt.cells) {
    double x = 0, y = 0, z = 0;
    for (uint32_t v : c)
      x += grid[v].x / 4.0 - 127.875, y += grid[v].y / 4.0 - 127.875, z += grid[v].z / 4.0 - 127.875;
    if (std::hypot(std::hypot(x, y) - 300, z) < 150) torus.push_back(c);
  }
  EncodeInput in;
  in.points = points;
  in.tetrahedra = torus;
  EncodeOptions options;
  options.qbits = 10;
  options.dmax = 40;
  const StatusOr<EncodedMesh> first = encode(in, options);
  ASSERT_TRUE(first.ok()) << first.status().message();
  EXPECT_GE(first->report.levels.size(), 3u);
  EXPECT_EQ(encode(in, options).value().bytes, first->bytes);
}

}  // namespace
}  // namespace dtm
