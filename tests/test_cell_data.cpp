// Cell data (spec/FORMAT.md §2.4, §3.8; core/cell_sources.h): level 0's
// cells carry the input's per-cell arrays, a cell that is an input
// tetrahedron its own values bit for bit, any other those of an input
// tetrahedron holding its centroid (found here by a search of every input
// tetrahedron, not the encoder's); coarser levels carry none; lossy arrays
// stay within their bound; damaged tables and sections are refused, every
// truncation ends cleanly; the readers and writers of VTU, VTK and gmsh
// carry the arrays.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <thread>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/region_decode.h"
#include "codec/sections/cell_value_coder.h"
#include "codec/stream/format.h"
#include "core/quantize.h"
#include "mesh/delaunay.h"
#include "mesh/topology.h"
#include "test_support.h"
#include "thread_ranks.h"
#include "tools/decoded_mesh.h"
#include "tools/field_types.h"
#include "tools/formats/input.h"
#include "tools/formats/mesh_writers.h"

namespace dtm {
namespace {

using Tet = std::array<uint32_t, 4>;
using P4 = std::array<int64_t, 3>;

// Random points on a 10-bit grid and their Delaunay tetrahedra; encoded on
// a coarser grid (7 bits), where quantization moves the points, so that
// level 0 (the Delaunay tetrahedralization of the moved points) has cells
// that are not the input's. Each tetrahedron's values name it: a float64
// t / 2 + 1/4, a float32 x 3 (t, -t, t / 8) and a uint8 t mod 7.
struct CellInput {
  std::vector<InputPoint> points;
  std::vector<Tet> tets;
  std::vector<double> pressure, stress, material;
  std::vector<EncodeInput::Field> fields() const {
    return {{"pressure", ValueType::kF64, 1, pressure},
            {"stress", ValueType::kF32, 3, stress},
            {"material", ValueType::kU8, 1, material}};
  }
};

CellInput block(size_t count, uint32_t seed) {
  CellInput in;
  const std::vector<GridPoint> g = test::random_grid_points(count, 10, seed);
  for (const GridPoint& p : g) in.points.push_back({double(p.x), double(p.y), double(p.z)});
  in.tets = delaunay_tetrahedralize(g).value().cells;
  for (size_t t = 0; t < in.tets.size(); ++t) {
    const double d = static_cast<double>(t);
    in.pressure.push_back(d / 2 + 0.25);
    in.stress.insert(in.stress.end(), {d, -d, d / 8});
    in.material.push_back(static_cast<double>(t % 7));
  }
  return in;
}

struct Encoded {
  std::vector<uint8_t> bytes;
  EncodeReport report;
};

Encoded encode_cells(const CellInput& in, const EncodeOptions& options) {
  const std::vector<EncodeInput::Field> fields = in.fields();
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.cell_fields = fields;
  auto encoded = encode(input, options);
  EXPECT_TRUE(encoded.ok()) << encoded.status().message();
  if (!encoded.ok()) return {};
  return {encoded->bytes, encoded->report};
}

EncodeOptions coarse_grid() {
  EncodeOptions o;
  o.qbits = 7;
  o.dmax = 20;
  return o;
}

int orientation(const P4& a, const P4& b, const P4& c, const P4& d) {
  const __int128 bx = b[0] - a[0], by = b[1] - a[1], bz = b[2] - a[2];
  const __int128 cx = c[0] - a[0], cy = c[1] - a[1], cz = c[2] - a[2];
  const __int128 dx = d[0] - a[0], dy = d[1] - a[1], dz = d[2] - a[2];
  const __int128 det = bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx);
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

bool holds(const std::array<P4, 4>& t, const P4& p) {
  const int o = orientation(t[0], t[1], t[2], t[3]);
  return o != 0 && orientation(p, t[1], t[2], t[3]) * o >= 0 && orientation(t[0], p, t[2], t[3]) * o >= 0 &&
         orientation(t[0], t[1], p, t[3]) * o >= 0 && orientation(t[0], t[1], t[2], p) * o >= 0;
}

P4 times4(const GridPoint& p) { return {4 * int64_t{p.x}, 4 * int64_t{p.y}, 4 * int64_t{p.z}}; }

// The input tetrahedron whose values a decoded cell carries: its pressure
// names it (t / 2 + 1/4, exact in float64).
uint32_t named(double pressure) { return static_cast<uint32_t>(std::lround((pressure - 0.25) * 2)); }

// In bricks of a few points, built in blocks of a few hundred: many chunks
// at level 0, each coding its cells' values alone (16.0, spec/FORMAT.md §3.5).
EncodeOptions coarse_grid_bricks() {
  EncodeOptions o = coarse_grid();
  o.bricks = true;
  o.brick_points = 24;
  o.block_points = 300;
  return o;
}

class CellDataStreams : public ::testing::TestWithParam<bool> {};
INSTANTIATE_TEST_SUITE_P(WholeAndBricked, CellDataStreams, ::testing::Bool(),
                         [](const auto& info) { return info.param ? "Bricked" : "Whole"; });

TEST_P(CellDataStreams, LevelZeroCarriesTheInputsValuesAndCoarserLevelsNone) {
  const bool bricked = GetParam();
  const CellInput in = block(1500, 5);
  const Encoded e = encode_cells(in, bricked ? coarse_grid_bricks() : coarse_grid());
  ASSERT_FALSE(e.bytes.empty());
  if (bricked) {
    const StreamSummary s = scan_stream(e.bytes);
    ASSERT_TRUE(s.status.ok()) << s.status.message();
    EXPECT_EQ(s.header.version_major, kVersionMajorBrickedCellData);
    EXPECT_GT(s.layers.back().chunks, 4u) << "level 0 in a few chunks: nothing to test";
    EXPECT_EQ(s.layers.back().header.cell_value_bytes, e.report.cell_value_bytes);
  }
  ASSERT_EQ(e.report.cell_fields.size(), 3u);
  EXPECT_GT(e.report.cells_from_input, 0u);
  ASSERT_LT(e.report.cells_from_input, e.report.level0_cells) << "every cell an input one: nothing to test";
  ASSERT_GE(e.report.levels.size(), 2u);

  // The input's tetrahedra on the encoder's grid.
  const QuantizedPoints q = quantize(in.points, 7).value();
  std::map<std::array<GridPoint, 4>, std::set<uint32_t>> by_corners;
  std::vector<std::array<P4, 4>> corners(in.tets.size());
  for (uint32_t t = 0; t < in.tets.size(); ++t) {
    std::array<GridPoint, 4> k;
    for (size_t i = 0; i < 4; ++i) {
      k[i] = q.points[q.input_to_point[in.tets[t][i]]];
      corners[t][i] = times4(k[i]);
    }
    std::sort(k.begin(), k.end());
    by_corners[k].insert(t);
  }

  ProgressiveDecoder decoder;
  int levels = 0;
  uint64_t exact = 0, holding = 0, elsewhere = 0;
  ASSERT_TRUE(decoder
                  .feed(e.bytes,
                        [&](const ProgressiveDecoder& d, const DecodedLevel& level) {
                          ++levels;
                          ASSERT_EQ(d.cell_field_table().size(), 3u);
                          const TetMesh dt = d.delaunay();
                          std::vector<uint32_t> order;
                          const std::vector<uint8_t> kept = d.carving(dt, order);
                          const std::vector<FieldValues> values = d.cell_data(dt, kept, order);
                          ASSERT_TRUE(d.mesh_status().ok()) << d.mesh_status().message();
                          if (level.level != 0) {
                            EXPECT_TRUE(values.empty()) << "level " << level.level;
                            return;
                          }
                          ASSERT_EQ(values.size(), 3u);
                          size_t k = 0;
                          for (uint32_t c : order) {
                            if (!kept[c]) continue;
                            const uint32_t t = named(values[0].value(k, 0));
                            ASSERT_LT(t, in.tets.size());
                            // Every array names the same input tetrahedron.
                            EXPECT_EQ(values[1].value(k, 1), -static_cast<double>(t));
                            EXPECT_EQ(values[1].value(k, 2), static_cast<double>(t) / 8);
                            EXPECT_EQ(values[2].value(k, 0), static_cast<double>(t % 7));
                            std::array<GridPoint, 4> corners_of;
                            P4 centre{0, 0, 0};
                            for (size_t i = 0; i < 4; ++i) {
                              corners_of[i] = d.points()[dt.cells[c][i]];
                              centre[0] += corners_of[i].x, centre[1] += corners_of[i].y,
                                  centre[2] += corners_of[i].z;
                            }
                            std::sort(corners_of.begin(), corners_of.end());
                            if (const auto it = by_corners.find(corners_of); it != by_corners.end()) {
                              EXPECT_TRUE(it->second.count(t)) << "an input cell with another's values";
                              ++exact;
                            } else if (holds(corners[t], centre)) {
                              ++holding;
                            } else {
                              ++elsewhere;
                            }
                            ++k;
                          }
                          EXPECT_EQ(k, e.report.level0_cells);
                        })
                  .ok());
  EXPECT_TRUE(decoder.finish().ok());
  EXPECT_EQ(levels, static_cast<int>(e.report.levels.size()));
  EXPECT_EQ(exact, e.report.cells_from_input);
  EXPECT_GT(holding, 0u);
  EXPECT_EQ(elsewhere, e.report.cells_from_nearest);
}

TEST(CellData, LossyArraysStayWithinTheirBound) {
  const CellInput in = block(800, 6);
  EncodeOptions o;
  o.field_errors["pressure"] = 0.01;
  const Encoded e = encode_cells(in, o);
  ASSERT_FALSE(e.bytes.empty());
  ASSERT_TRUE(e.report.cell_fields[0].description.lossy);
  // Here level 0 is nearly the input (Delaunay on a finer grid).
  EXPECT_GT(e.report.cells_from_input, e.report.level0_cells * 99 / 100);
  ProgressiveDecoder d;
  ASSERT_TRUE(decode_stream(e.bytes, d).ok());
  const OutputMesh m = decoded_mesh(d, "lossy");
  ASSERT_EQ(m.cell_fields.size(), 3u);
  const OutputField& p = m.cell_fields[0];
  const OutputField& stress = m.cell_fields[1];
  double worst = 0;
  for (size_t c = 0; c < m.cells.size(); ++c) {
    // The lossless stress names the tetrahedron; the pressure is within E.
    float t = 0;
    const uint32_t bits = static_cast<uint32_t>(stress.bits[3 * c]);
    std::memcpy(&t, &bits, 4);
    double v = 0;
    std::memcpy(&v, &p.bits[c], 8);
    worst = std::max(worst, std::abs(v - (t / 2 + 0.25)));
  }
  EXPECT_LE(worst, 0.01);
  EXPECT_GT(worst, 0.0);
}

TEST(CellData, StreamsWithoutThemAreAsBefore) {
  const CellInput in = block(500, 7);
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  auto plain = encode(input, EncodeOptions{});
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain->bytes[8], kVersionMajorUnbricked);
  const Encoded with = encode_cells(in, EncodeOptions{});
  EXPECT_EQ(with.bytes[8], kVersionMajorCellData);
  // The same levels: only the table and level 0's section differ.
  ProgressiveDecoder a, b;
  ASSERT_TRUE(decode_stream(plain->bytes, a).ok());
  ASSERT_TRUE(decode_stream(with.bytes, b).ok());
  EXPECT_EQ(a.points(), b.points());
  EXPECT_EQ(a.carved_cells(), b.carved_cells());
}

TEST(CellData, RefusedWhereTheStreamCannotCarryThem) {
  const CellInput in = block(300, 8);
  std::vector<EncodeInput::Field> fields = in.fields();
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.cell_fields = fields;
  // In bricks, yes (16.0); on ranks each must be given every tetrahedron
  // (a cell's source may be any at its corners), and a rank given only
  // some makes every rank refuse.
  EncodeOptions bricks;
  bricks.bricks = true;
  EXPECT_TRUE(encode(input, bricks).ok());
  const std::vector<Tet> half(in.tets.begin(),
                              in.tets.begin() + static_cast<std::ptrdiff_t>(in.tets.size() / 2));
  std::vector<EncodeInput::Field> half_fields = in.fields();
  for (auto& f : half_fields) f.values = f.values.first(half.size() * static_cast<size_t>(f.components));
  // (Rank 1's input made by `given`.)
  const auto codes = [&](const std::function<void(EncodeInput&)>& given) {
    return test::on_ranks(2, true, [&](RankExchange& rank, int r) {
      EncodeOptions on_rank = bricks;
      on_rank.exchange = &rank;
      EncodeInput mine = input;
      if (r == 1) given(mine);
      return encode(mine, on_rank).status().code();
    });
  };
  const std::vector<StatusCode> refused(2, StatusCode::kInvalidInput);
  EXPECT_EQ(codes([&](EncodeInput& i) { i.tetrahedra = half, i.cell_fields = half_fields; }), refused);
  // A rank given no tetrahedron (nor values), or no cell data at all, where
  // the other has them: every rank refuses, none waits for the others.
  std::vector<EncodeInput::Field> none = in.fields();
  for (auto& f : none) f.values = {};
  EXPECT_EQ(codes([&](EncodeInput& i) { i.tetrahedra = {}, i.cell_fields = none; }), refused);
  EXPECT_EQ(codes([&](EncodeInput& i) { i.cell_fields = {}; }), refused);
  EXPECT_EQ(encode(input, EncodeOptions::paper()).status().code(), StatusCode::kInvalidInput);
  std::vector<double> short_values(3);
  fields[0].values = short_values;
  EXPECT_EQ(encode(input, EncodeOptions{}).status().code(), StatusCode::kInvalidInput);
  fields = in.fields();  // (a new vector: the spans are set again)
  input.cell_fields = fields;
  fields[1].name = "pressure";
  EXPECT_EQ(encode(input, EncodeOptions{}).status().code(), StatusCode::kInvalidInput);
  EncodeInput points_only;
  points_only.points = in.points;
  fields = in.fields();
  input.cell_fields = fields;
  points_only.cell_fields = fields;
  EXPECT_EQ(encode(points_only, EncodeOptions{}).status().code(), StatusCode::kInvalidInput);
  // A NaN in a lossy array.
  std::vector<double> with_nan = in.pressure;
  with_nan[5] = NAN;
  fields[0].values = with_nan;
  EncodeOptions lossy;
  lossy.field_errors["pressure"] = 0.1;
  EXPECT_EQ(encode(input, lossy).status().code(), StatusCode::kInvalidInput);
}

// A bricked level 0 read by box and in pieces (spec/FORMAT.md §4.1): each
// cell with the values the whole decoder gives it; the pieces' cells are the
// level's, each once, with its values; a coarser level's box has none.
TEST(CellData, BricksGiveABoxOrAPieceItsCellsValues) {
  const CellInput in = block(1500, 5);
  const Encoded e = encode_cells(in, coarse_grid_bricks());
  ASSERT_FALSE(e.bytes.empty());
  ProgressiveDecoder whole;
  ASSERT_TRUE(whole.feed(e.bytes).ok());
  ASSERT_TRUE(whole.finish().ok());
  // The whole level 0: each cell (by its corners) and its values.
  using Corners = std::array<GridPoint, 4>;
  const auto by_corners = [](const RegionMesh& m) {
    std::map<Corners, std::vector<uint64_t>> out;
    for (size_t c = 0; c < m.cells.size(); ++c) {
      Corners k;
      for (size_t i = 0; i < 4; ++i) k[i] = m.points[m.cells[c][i]];
      std::sort(k.begin(), k.end());
      std::vector<uint64_t>& bits = out[k];
      EXPECT_TRUE(bits.empty()) << "a cell twice";
      for (const FieldValues& f : m.cell_fields) {
        const auto n = static_cast<size_t>(f.description.components);
        bits.insert(bits.end(), f.bits.begin() + static_cast<std::ptrdiff_t>(c * n),
                    f.bits.begin() + static_cast<std::ptrdiff_t>((c + 1) * n));
      }
    }
    return out;
  };
  const GridBox everything{{0, 0, 0}, {127, 127, 127}};
  const RegionMesh all = region_of(whole, everything);
  ASSERT_EQ(all.cell_fields.size(), 3u);
  ASSERT_EQ(all.cells.size(), e.report.level0_cells);
  const auto want = by_corners(all);
  for (const GridBox& box :
       {GridBox{{0, 0, 0}, {63, 63, 63}}, GridBox{{40, 20, 30}, {90, 100, 70}}, everything}) {
    MemorySource source(e.bytes);
    const auto got = decode_region(source, box, 0);
    ASSERT_TRUE(got.ok()) << got.status().message();
    EXPECT_TRUE(got->bricked);
    ASSERT_EQ(got->cell_fields.size(), 3u);
    const RegionMesh expected = region_of(whole, box);
    EXPECT_TRUE(got->cells == expected.cells);
    for (size_t f = 0; f < 3; ++f) EXPECT_TRUE(got->cell_fields[f].bits == expected.cell_fields[f].bits) << f;
  }
  std::map<Corners, std::vector<uint64_t>> pieces;
  for (int piece = 0; piece < 4; ++piece) {
    MemorySource source(e.bytes);
    const auto got = decode_piece(source, 0, piece, 4);
    ASSERT_TRUE(got.ok()) << got.status().message();
    ASSERT_EQ(got->cell_fields.size(), 3u) << "an empty piece declares the arrays too";
    for (auto& [k, bits] : by_corners(*got))
      EXPECT_TRUE(pieces.emplace(k, bits).second) << "a cell in two pieces";
  }
  EXPECT_TRUE(pieces == want);
  // Level 1 has no cell data.
  MemorySource source(e.bytes);
  const auto coarser = decode_region(source, everything, 1);
  ASSERT_TRUE(coarser.ok()) << coarser.status().message();
  EXPECT_GT(coarser->cells.size(), 0u);
  EXPECT_TRUE(coarser->cell_fields.empty());
}

// On the ranks of a run (each given every tetrahedron and its values), the
// bytes one process writes, whichever way the ranks answer each other.
TEST(CellData, BrickedStreamsAreTheSameBytesOnAnyNumberOfRanks) {
  const CellInput in = block(1500, 12);
  EncodeOptions options = coarse_grid_bricks();
  options.field_errors["pressure"] = 0.75;  // a lossy array's scales are every tetrahedron's too
  const Encoded alone = encode_cells(in, options);
  ASSERT_FALSE(alone.bytes.empty());
  ASSERT_GT(alone.report.cell_value_bytes, 0u);
  ASSERT_GT(alone.report.level0_cells, alone.report.cells_from_input) << "no cell takes another's values";
  for (const bool at_once : {true, false}) {
    for (int ranks : {2, 3}) {
      SCOPED_TRACE(std::to_string(ranks) + (at_once ? " ranks answering while they work" : " ranks"));
      const std::vector<Encoded> made = test::on_ranks(ranks, at_once, [&](RankExchange& rank, int) {
        EncodeOptions on_rank = options;
        on_rank.exchange = &rank;
        return encode_cells(in, on_rank);
      });
      for (const Encoded& e : made) {
        EXPECT_TRUE(e.bytes == alone.bytes);
        EXPECT_EQ(e.report.cells_from_input, alone.report.cells_from_input);
        EXPECT_EQ(e.report.cell_value_bytes, alone.report.cell_value_bytes);
      }
    }
  }
}

// Every prefix decodes to whole levels (level 0 only whole, with its
// values) or stops as truncated; every bit flipped in the cell field table
// is caught; the decoder's value limit holds for the cells too.
TEST_P(CellDataStreams, TruncatedDamagedAndOversizedStreamsEndCleanly) {
  const CellInput in = block(400, 9);
  EncodeOptions options;  // (the default grid: level 0 in many chunks)
  options.bricks = GetParam();
  options.brick_points = 24;
  options.block_points = 300;
  const Encoded e = encode_cells(in, options);
  ASSERT_FALSE(e.bytes.empty());
  for (size_t len = 0; len < e.bytes.size(); len += (len < 300 ? 1 : 53)) {
    ProgressiveDecoder d;
    ASSERT_TRUE(d.feed(std::span(e.bytes).first(len)).ok()) << len;
    EXPECT_EQ(d.finish().code(), StatusCode::kTruncated) << len;
    if (d.finest_level() >= 0) {
      const OutputMesh m = decoded_mesh(d, "prefix");
      EXPECT_TRUE(m.cell_fields.empty()) << len;
    }
  }
  const StreamSummary s = scan_stream(e.bytes);
  ASSERT_TRUE(s.status.ok()) << s.status.message();
  ASSERT_EQ(s.cell_fields.size(), 3u);
  const size_t begin = kHeaderSize + s.tables_bytes() - s.cell_field_table_bytes;
  for (size_t byte = begin; byte < begin + s.cell_field_table_bytes; ++byte)
    for (int bit = 0; bit < 8; bit += 3) {
      std::vector<uint8_t> damaged = e.bytes;
      damaged[byte] ^= static_cast<uint8_t>(1 << bit);
      ProgressiveDecoder d;
      const Status fed = d.feed(damaged);
      EXPECT_TRUE(!fed.ok() || !d.finish().ok()) << "byte " << byte << " bit " << bit;
    }
  DecoderOptions small;
  small.max_values = e.report.level0_cells * 5 - 1;  // one value short of the 5 components' room
  ProgressiveDecoder limited(small);
  ASSERT_TRUE(limited.feed(e.bytes).ok());
  const TetMesh dt = limited.delaunay();
  std::vector<uint32_t> order;
  const std::vector<uint8_t> kept = limited.carving(dt, order);
  EXPECT_TRUE(limited.cell_data(dt, kept, order).empty());
  EXPECT_EQ(limited.mesh_status().code(), StatusCode::kLimitExceeded);
  if (GetParam()) {  // a bricked level 0 read by box holds the limit too, and no more
    const GridBox everything{{0, 0, 0}, {1 << 20, 1 << 20, 1 << 20}};
    MemorySource source(e.bytes);
    EXPECT_EQ(decode_region(source, everything, 0, small).status().code(), StatusCode::kLimitExceeded);
    small.max_values += 1;
    const auto whole = decode_region(source, everything, 0, small);
    ASSERT_TRUE(whole.ok()) << whole.status().message();
    EXPECT_EQ(whole->cells.size(), e.report.level0_cells);
  }
}

// Level 0 alone (no coarser level is built): its base layer, one chunk,
// codes its cells' values again (BrickedEncoder::write), from the input's
// tetrahedra still held.
TEST(CellData, ABrickedStreamOfOneLevelKeepsThem) {
  const CellInput in = block(600, 4);
  EncodeOptions o = coarse_grid_bricks();
  o.min_base_vertices = size_t{1} << 30;
  const Encoded e = encode_cells(in, o);
  ASSERT_EQ(e.report.levels.size(), 1u);
  ProgressiveDecoder d;
  ASSERT_TRUE(d.feed(e.bytes).ok());
  ASSERT_TRUE(d.finish().ok());
  const ProgressiveDecoder::LevelCells level = d.level_cells();
  const std::vector<FieldValues> values = d.cell_data(level.mesh, level.kept, level.order);
  ASSERT_TRUE(d.mesh_status().ok()) << d.mesh_status().message();
  ASSERT_EQ(values.size(), 3u);
  ASSERT_EQ(values[0].bits.size(), e.report.level0_cells);
  for (size_t k = 0; k < values[0].bits.size(); ++k) {
    const uint32_t t = named(values[0].value(k, 0));
    ASSERT_LT(t, in.tets.size());
    EXPECT_EQ(values[2].value(k, 0), static_cast<double>(t % 7));
  }
}

// Below the layer checksum: a damaged cell value section is refused or
// gives every cell its values.
TEST(CellData, DamagedSectionsGiveValuesOrAnError) {
  const std::vector<GridPoint> g = test::random_grid_points(120, 8, 3);
  const TetMesh dt = delaunay_tetrahedralize(g).value();
  std::vector<std::array<uint32_t, 4>> cells;
  for (uint32_t c : canonical_cell_order(dt.cells)) cells.push_back(dt.cells[c]);
  const std::vector<GridPoint> at = cell_positions(g, cells);
  FieldValues f;
  f.description.name = "heat";
  f.description.type = ValueType::kF64;
  for (size_t c = 0; c < cells.size(); ++c)
    f.bits.push_back(bits_of(std::sin(0.01 * at[c].x) + c % 3, f.description.type));
  const std::vector<uint64_t> original = f.bits;
  auto coder = FieldSectionEncoder::make({f});
  ASSERT_TRUE(coder.ok());
  std::vector<uint32_t> ids(cells.size());
  std::iota(ids.begin(), ids.end(), 0u);
  std::vector<uint64_t> bytes;
  const std::vector<uint8_t> section = coder->encode_layer(ids, at, bytes);
  std::vector<FieldValues> out;
  ASSERT_TRUE(decode_cell_values(coder->descriptions(), section, at, out).ok());
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].bits, original);
  int refused = 0;
  for (size_t byte = 0; byte < section.size(); byte += 11)
    for (int bit = 0; bit < 8; bit += 2) {
      std::vector<uint8_t> damaged = section;
      damaged[byte] ^= static_cast<uint8_t>(1 << bit);
      const Status s = decode_cell_values(coder->descriptions(), damaged, at, out);
      if (!s.ok()) {
        EXPECT_EQ(s.code(), StatusCode::kCorrupt);
        ++refused;
        continue;
      }
      ASSERT_EQ(out[0].bits.size(), cells.size());
    }
  EXPECT_GT(refused, 0);
  for (size_t len = 0; len < section.size(); len += 5)
    EXPECT_EQ(decode_cell_values(coder->descriptions(), std::span(section).first(len), at, out).code(),
              StatusCode::kCorrupt)
        << len;

  // A bricked level 0's chunks (16.0): three, each cell's by its second
  // vertex, every other cell kept.
  std::vector<uint32_t> chunk_of_cell(dt.cells.size()), rank(g.size());
  std::iota(rank.begin(), rank.end(), 0u);
  std::vector<uint8_t> kept(dt.cells.size());
  for (size_t c = 0; c < dt.cells.size(); ++c) chunk_of_cell[c] = dt.cells[c][1] % 3, kept[c] = c % 2;
  const ChunkCells chunks = chunk_cells(dt, chunk_of_cell, 3, rank);
  FieldValues per_cell = f;  // the cells' values by their index in dt
  per_cell.bits.clear();
  for (size_t c = 0; c < dt.cells.size(); ++c)
    per_cell.bits.push_back(bits_of(0.5 * double(c), f.description.type));
  auto cell_coder = FieldSectionEncoder::make({per_cell});
  ASSERT_TRUE(cell_coder.ok());
  const auto sections = encode_cell_value_chunks(
      *cell_coder, dt, g, chunks, kept, [](uint32_t c) { return c; }, bytes);
  ASSERT_EQ(sections.size(), 3u);
  std::vector<std::span<const uint8_t>> parts(sections.begin(), sections.end());
  ASSERT_TRUE(
      decode_cell_value_chunks(cell_coder->descriptions(), parts, dt, g, chunks, chunk_of_cell, kept, out)
          .ok());
  // The kept cells' values, in their index order.
  std::vector<uint64_t> kept_bits;
  for (size_t c = 0; c < dt.cells.size(); ++c)
    if (kept[c]) kept_bits.push_back(per_cell.bits[c]);
  EXPECT_EQ(out[0].bits, kept_bits);
  const auto is_refused = [&](std::span<const std::span<const uint8_t>> p, std::span<const uint32_t> of,
                              std::span<const uint8_t> k) {
    return decode_cell_value_chunks(cell_coder->descriptions(), p, dt, g, chunks, of, k, out).code() ==
           StatusCode::kCorrupt;
  };
  // Kept cells without a section, a section without kept cells, a kept
  // cell whose brick has no chunk, every truncation and some bit flips.
  std::vector<std::span<const uint8_t>> missing = parts;
  missing[1] = {};
  EXPECT_TRUE(is_refused(missing, chunk_of_cell, kept));
  std::vector<uint8_t> none_kept = kept;
  for (size_t c = 0; c < dt.cells.size(); ++c)
    if (chunk_of_cell[c] == 2) none_kept[c] = 0;
  EXPECT_TRUE(is_refused(parts, chunk_of_cell, none_kept));
  std::vector<uint32_t> orphan = chunk_of_cell;
  orphan[1] = kNoCarvingChunk;  // cell 1 is kept
  EXPECT_TRUE(is_refused(parts, orphan, kept));
  for (size_t len = 0; len < sections[0].size(); ++len) {
    std::vector<std::span<const uint8_t>> cut = parts;
    cut[0] = cut[0].first(len);
    EXPECT_TRUE(is_refused(cut, chunk_of_cell, kept)) << len;
  }
  for (size_t byte = 0; byte < sections[2].size(); byte += 3) {
    std::vector<uint8_t> damaged = sections[2];
    damaged[byte] ^= 0x21;
    std::vector<std::span<const uint8_t>> flipped = parts;
    flipped[2] = damaged;
    const Status s = decode_cell_value_chunks(cell_coder->descriptions(), flipped, dt, g, chunks,
                                              chunk_of_cell, kept, out);
    EXPECT_TRUE(s.ok() || s.code() == StatusCode::kCorrupt) << byte;
  }
}

// The writers put the arrays where their formats hold cell data, and the
// readers take them back, bit for bit, in their types.
TEST(CellData, ReadersAndWritersCarryTheArrays) {
  const auto dir = std::filesystem::temp_directory_path() / ("dtm_cells_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  OutputMesh m;
  m.grid.step = 0.5;
  m.grid.qbits = 6;
  m.points = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}, {10, 10, 10}};
  m.cells = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  m.region = {4, 9};
  m.faces = {{0, 1, 2}};
  m.face_tags = {3};
  const auto f64 = [](double v) { return bits_of(v, ValueType::kF64); };
  const auto f32 = [](double v) { return bits_of(v, ValueType::kF32); };
  m.cell_fields.push_back({"von mises", ScalarType::kFloat64, 1, {f64(1.5e8), f64(-0.125)}});
  m.cell_fields.push_back(
      {"velocity", ScalarType::kFloat32, 3, {f32(1), f32(2), f32(3), f32(-4), f32(0.5), f32(6)}});
  m.cell_fields.push_back(
      {"zone", ScalarType::kInt32, 1, {bits_of(-3, ValueType::kI32), bits_of(70000, ValueType::kI32)}});
  for (const auto& [format, ext] :
       std::vector<std::pair<MeshFormat, std::string>>{{MeshFormat::kVtu, ".vtu"},
                                                       {MeshFormat::kVtuAscii, ".vtu"},
                                                       {MeshFormat::kVtk, ".vtk"},
                                                       {MeshFormat::kVtkAscii, ".vtk"},
                                                       {MeshFormat::kGmsh, ".msh"}}) {
    const std::string path = (dir / ("cells" + ext)).string();
    for (const auto& [file, text] : render_mesh(m, format, path))
      std::ofstream(file, std::ios::binary) << text;
    InputMesh in = read_input(path);
    choose_regions(in, "", path);
    SCOPED_TRACE(path);
    ASSERT_EQ(in.tets.size(), 2u);
    // The arrays' rows on the tagged face are 0, no value: meshdec's own
    // file is read back with nothing left out (--strict takes it).
    EXPECT_TRUE(in.left_out.empty()) << in.left_out.front();
    std::map<std::string, const VertexField*> by_name;
    for (const VertexField& f : in.cell_fields) by_name[f.name] = &f;
    for (const OutputField& f : m.cell_fields) {
      ASSERT_TRUE(by_name.count(f.name)) << f.name;
      const VertexField& g = *by_name[f.name];
      EXPECT_EQ(g.components, f.components);
      ASSERT_EQ(g.values.size(), f.bits.size());
      for (size_t i = 0; i < f.bits.size(); ++i)
        EXPECT_EQ(bits_of(g.values[i], value_type(f.type)), f.bits[i]) << f.name << " " << i;
      // VTU and VTK keep the array's own type; gmsh's $ElementData is float64.
      if (format != MeshFormat::kGmsh) {
        EXPECT_EQ(g.type, f.type) << f.name;
      }
    }
  }
  std::filesystem::remove_all(dir);
}

// A parallel grid (.pvtu naming two .vtu pieces, as ParaView's parallel
// writers and meshdec --pieces write one) reads as one mesh: the pieces'
// points one after the other, a point a later piece repeats (at exactly an
// earlier piece's coordinates) merged into the first copy, their cells
// renumbered, their arrays joined. Values of a copy that differ from the
// first's are said (this grid's pieces give the three shared points others).
TEST(CellData, AParallelGridReadsAsOneMesh) {
  const auto dir = std::filesystem::temp_directory_path() / ("dtm_pvtu_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  OutputMesh a;
  a.grid.step = 1;
  a.grid.qbits = 6;
  a.points = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  a.cells = {{0, 1, 2, 3}};
  a.fields.push_back({"heat", ScalarType::kFloat32, 1, {}});
  for (double v : {1.0, 2.0, 3.0, 4.0}) a.fields[0].bits.push_back(bits_of(v, ValueType::kF32));
  a.cell_fields.push_back({"stress", ScalarType::kFloat64, 1, {bits_of(7.5, ValueType::kF64)}});
  a.region = {3};
  OutputMesh b = a;
  b.points = {{10, 0, 0}, {0, 10, 0}, {0, 0, 10}, {10, 10, 10}};
  b.cell_fields[0].bits = {bits_of(-1.25, ValueType::kF64)};
  const std::vector<std::string> pieces = {"part_0.vtu", "part_1.vtu"};
  std::ofstream((dir / pieces[0]).string())
      << render_mesh(a, MeshFormat::kVtu, (dir / pieces[0]).string())[0].second;
  std::ofstream((dir / pieces[1]).string())
      << render_mesh(b, MeshFormat::kVtu, (dir / pieces[1]).string())[0].second;
  std::ofstream((dir / "part.pvtu").string()) << render_pvtu(a, pieces);
  InputMesh in = read_input((dir / "part.pvtu").string());
  choose_regions(in, "", "part.pvtu");
  ASSERT_EQ(in.points.size(), 5u);
  ASSERT_EQ(in.tets.size(), 2u);
  EXPECT_EQ(in.tets[1], (std::array<uint32_t, 4>{1, 2, 3, 4}));
  EXPECT_EQ(in.tet_regions, (std::vector<int32_t>{3, 3}));
  ASSERT_EQ(in.cell_fields.size(), 1u);
  EXPECT_EQ(in.cell_fields[0].values, (std::vector<double>{7.5, -1.25}));
  ASSERT_EQ(in.fields.size(), 1u);
  EXPECT_EQ(in.fields[0].values, (std::vector<double>{1, 2, 3, 4, 4}));
  EXPECT_NE(std::find_if(in.left_out.begin(), in.left_out.end(),
                         [](const std::string& s) {
                           return s.find("the values at 3 copies of points the pieces share") == 0;
                         }),
            in.left_out.end());
  // A piece that is not there is an error naming it.
  std::filesystem::remove(dir / pieces[1]);
  EXPECT_THROW(read_input((dir / "part.pvtu").string()), FormatError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dtm
