// Format 7.0's candidate section (spec/FORMAT.md §3.4): the candidates are
// the exact, order-independent places the spec defines; the section sends
// back exactly the points the encoder marks; damaged sections and sections
// that send known or repeated points are refused; and a TetGen mesh's
// finer layers use it and still decode to the encoder's levels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/sections/candidate_coder.h"
#include "codec/stream/format.h"
#include "codec/stream/format_encoder.h"
#include "test_support.h"
#include "tools/formats/tetgen.h"

namespace dtm {
namespace {

constexpr int kQ = 10;

std::vector<MortonCode> codes_of(std::span<const GridPoint> points, int qbits = kQ) {
  std::vector<MortonCode> out;
  for (const GridPoint& p : points) out.push_back(morton_encode(p, qbits));
  std::sort(out.begin(), out.end());
  return out;
}

// The circumcentre in doubles, for comparison.
std::array<double, 3> circumcentre(const std::array<GridPoint, 4>& p) {
  double a[3][3], len[3];
  for (int i = 0; i < 3; ++i) {
    a[i][0] = p[i + 1].x - p[0].x, a[i][1] = p[i + 1].y - p[0].y, a[i][2] = p[i + 1].z - p[0].z;
    len[i] = a[i][0] * a[i][0] + a[i][1] * a[i][1] + a[i][2] * a[i][2];
  }
  auto cross = [](const double* u, const double* v, double* w) {
    w[0] = u[1] * v[2] - u[2] * v[1], w[1] = u[2] * v[0] - u[0] * v[2], w[2] = u[0] * v[1] - u[1] * v[0];
  };
  double bc[3], ca[3], ab[3];
  cross(a[1], a[2], bc), cross(a[2], a[0], ca), cross(a[0], a[1], ab);
  const double d = 2 * (a[0][0] * bc[0] + a[0][1] * bc[1] + a[0][2] * bc[2]);
  return {p[0].x + (len[0] * bc[0] + len[1] * ca[0] + len[2] * ab[0]) / d,
          p[0].y + (len[0] * bc[1] + len[1] * ca[1] + len[2] * ab[1]) / d,
          p[0].z + (len[0] * bc[2] + len[1] * ca[2] + len[2] * ab[2]) / d};
}

TEST(LayerCandidates, ACellsCircumcentreIsRoundedExactlyWhateverItsVertexOrder) {
  const std::vector<GridPoint> points = {{100, 100, 100}, {140, 100, 100}, {100, 140, 100}, {100, 100, 140}};
  const auto known = codes_of(points);
  std::array<uint32_t, 4> cell = {0, 1, 2, 3};
  std::vector<GridPoint> first;
  do {  // every order and both orientations
    const std::array<std::array<uint32_t, 4>, 1> cells = {cell};
    const auto c = layer_candidates(cells, points, known, kQ, kCandidateCellCentres);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c.at(0), (GridPoint{120, 120, 120}));
    EXPECT_EQ(c.code(0), morton_encode(c.at(0), kQ));
    // The nearest vertex at 1200 (11 bits), the shortest edge 1600 (11 bits).
    EXPECT_EQ(c.context(0), 2);
  } while (std::next_permutation(cell.begin(), cell.end()));
}

TEST(LayerCandidates, CircumcentresAreTheNearestGridPointsOfTheTrueOnes) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int32_t> coord(300, 700);
  int checked = 0;
  for (int t = 0; t < 2000; ++t) {
    std::array<GridPoint, 4> p;
    for (auto& q : p) q = {coord(rng), coord(rng), coord(rng)};
    const std::array<std::array<uint32_t, 4>, 1> cells = {{{0, 1, 2, 3}}};
    const std::vector<GridPoint> points(p.begin(), p.end());
    const auto c = layer_candidates(cells, points, {}, kQ, kCandidateCellCentres);
    const auto exact = circumcentre(p);
    const bool inside = std::all_of(exact.begin(), exact.end(), [](double v) { return v > 1 && v < 1022; });
    if (!inside) continue;  // may fall outside the grid, or be a flat cell's far centre
    ASSERT_EQ(c.size(), 1u) << t;
    const GridPoint at = c.at(0);
    EXPECT_LE(std::abs(at.x - exact[0]), 0.5 + 1e-6) << t;
    EXPECT_LE(std::abs(at.y - exact[1]), 0.5 + 1e-6) << t;
    EXPECT_LE(std::abs(at.z - exact[2]), 0.5 + 1e-6) << t;
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

TEST(LayerCandidates, LargeCellsAndCentresOutsideTheGridGiveNone) {
  // Spanning 2^13 grid steps on x: no circumcentre (q = 14).
  const std::vector<GridPoint> wide = {{0, 0, 0}, {8192, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  const std::array<std::array<uint32_t, 4>, 1> cell = {{{0, 1, 2, 3}}};
  EXPECT_TRUE(layer_candidates(cell, wide, codes_of(wide, 14), 14, kCandidateCellCentres).empty());
  const std::vector<GridPoint> narrower = {{0, 0, 0}, {8190, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  EXPECT_EQ(layer_candidates(cell, narrower, codes_of(narrower, 14), 14, kCandidateCellCentres).size(), 1u);
  // A flat cell near the grid's corner: its centre lies outside.
  const std::vector<GridPoint> flat = {{0, 0, 0}, {20, 0, 0}, {0, 20, 0}, {10, 10, 1}};
  EXPECT_TRUE(layer_candidates(cell, flat, codes_of(flat), kQ, kCandidateCellCentres).empty());
}

TEST(LayerCandidates, EveryEdgeGivesItsMidpointRoundedHalfUpOnce) {
  const std::vector<GridPoint> points = {
      {10, 10, 10}, {13, 10, 10}, {10, 15, 10}, {10, 10, 11}, {14, 14, 14}};
  // Two cells sharing the face 1-2-3: 9 edges.
  const std::array<std::array<uint32_t, 4>, 2> cells = {{{0, 1, 2, 3}, {4, 1, 2, 3}}};
  const auto c = layer_candidates(cells, points, codes_of(points), kQ, kCandidateEdgeMidpoints);
  ASSERT_EQ(c.size(), 8u);  // edge 0-3's midpoint, (10, 10, 11), is vertex 3
  const auto has = [&](GridPoint p) {
    for (size_t i = 0; i < c.size(); ++i)
      if (c.at(i) == p) return true;
    return false;
  };
  EXPECT_TRUE(has({12, 10, 10}));  // (10 + 13 + 1) / 2
  EXPECT_TRUE(has({10, 13, 10}));  // (10 + 15 + 1) / 2
  EXPECT_FALSE(has({10, 10, 11}));
  for (size_t i = 1; i < c.size(); ++i) EXPECT_LT(c.code(i - 1), c.code(i));
  for (size_t i = 0; i < c.size(); ++i) {
    EXPECT_GE(c.context(i), kCentreContexts);
    EXPECT_LT(c.context(i), kCandidateContexts);
  }
}

// A coarse level and a layer of which about half lie beside its candidates.
struct Layer {
  std::vector<GridPoint> coarse, fresh;
  TetMesh dt;
  CandidateList candidates;
};

// The coarse points in the order a decoder numbers them: a base layer comes
// out in Morton order.
Layer layer_over(std::vector<GridPoint> coarse) {
  Layer l;
  std::sort(coarse.begin(), coarse.end(), [](const GridPoint& a, const GridPoint& b) {
    return morton_encode(a, kQ) < morton_encode(b, kQ);
  });
  l.coarse = std::move(coarse);
  l.dt = delaunay_tetrahedralize(l.coarse).value();
  l.candidates = layer_candidates(l.dt.cells, l.coarse, codes_of(l.coarse), kQ, kKnownCandidateKinds);
  return l;
}

Layer make_layer(uint32_t seed) {
  Layer l = layer_over(test::random_grid_points(300, kQ, seed));
  const auto known = codes_of(l.coarse);
  std::mt19937 rng(seed);
  std::set<GridPoint> fresh;
  for (size_t i = 0; i < l.candidates.size(); i += 2) {
    const GridPoint c = l.candidates.at(i);
    const GridPoint p{c.x + static_cast<int32_t>(rng() % 3) - 1, c.y + static_cast<int32_t>(rng() % 3) - 1,
                      c.z + static_cast<int32_t>(rng() % 3) - 1};
    if (p.x < 0 || p.y < 0 || p.z < 0 || p.x >= (1 << kQ) || p.y >= (1 << kQ) || p.z >= (1 << kQ)) continue;
    if (!std::binary_search(known.begin(), known.end(), morton_encode(p, kQ))) fresh.insert(p);
  }
  for (const GridPoint& p : test::random_grid_points(200, kQ, seed + 1))
    if (!std::binary_search(known.begin(), known.end(), morton_encode(p, kQ))) fresh.insert(p);
  l.fresh.assign(fresh.begin(), fresh.end());
  return l;
}

TEST(CandidateSection, SendsBackExactlyThePointsItMarks) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const Layer l = make_layer(seed);
    std::vector<uint8_t> sent;
    const auto section = encode_candidate_section(l.candidates, l.fresh, sent);
    std::vector<GridPoint> marked;
    for (size_t i = 0; i < l.fresh.size(); ++i)
      if (sent[i]) marked.push_back(l.fresh[i]);
    EXPECT_GT(marked.size(), l.fresh.size() / 3) << seed;
    std::vector<GridPoint> decoded;
    ASSERT_TRUE(
        decode_candidate_section(section, l.candidates, static_cast<uint32_t>(l.fresh.size()), decoded).ok());
    EXPECT_EQ(codes_of(decoded), codes_of(marked)) << seed;
    // At fewer points allowed than it sends, it is refused.
    std::vector<GridPoint> capped;
    EXPECT_EQ(
        decode_candidate_section(section, l.candidates, static_cast<uint32_t>(marked.size() - 1), capped)
            .code(),
        StatusCode::kCorrupt);
  }
}

TEST(CandidateSection, EveryTruncationAndBitFlipEndsCleanly) {
  const Layer l = make_layer(4);
  std::vector<uint8_t> sent;
  const auto section = encode_candidate_section(l.candidates, l.fresh, sent);
  const auto max_points = static_cast<uint32_t>(l.fresh.size());
  for (size_t cut = 0; cut < section.size(); ++cut) {
    std::vector<GridPoint> out;
    const Status s = decode_candidate_section(std::span(section).first(cut), l.candidates, max_points, out);
    EXPECT_EQ(s.code(), StatusCode::kCorrupt) << "cut at " << cut;
  }
  for (size_t i = 0; i < section.size(); ++i)
    for (int b = 0; b < 8; ++b) {
      auto damaged = section;
      damaged[i] ^= static_cast<uint8_t>(1 << b);
      std::vector<GridPoint> out;
      const Status s = decode_candidate_section(damaged, l.candidates, max_points, out);
      // Below the layer checksum a flip may still decode, to points inside
      // the grid and no more than allowed.
      if (s.ok()) {
        EXPECT_LE(out.size(), max_points);
      } else {
        EXPECT_EQ(s.code(), StatusCode::kCorrupt);
      }
    }
}

// A two-layer stream: the base `coarse`, then a layer whose candidate
// section sends `beside` and whose payload codes `rest`.
std::vector<uint8_t> two_layer_stream(const Layer& l, std::span<const GridPoint> fresh, uint8_t kinds,
                                      bool base_kinds = false) {
  StreamHeader h;
  h.version_major = kVersionMajor;
  h.grid.qbits = kQ;
  h.level_count = 2;
  h.vertex_count = static_cast<uint32_t>(l.coarse.size() + fresh.size());
  SetCoderModels models;
  models.enable_coordinate_reuse(kQ);
  auto bytes = write_header(h);
  LayerHeader base;
  base.format_major = kVersionMajor;
  base.level = 1;
  base.new_vertices = base.level_vertices = static_cast<uint32_t>(l.coarse.size());
  base.alpha = 1e9;
  base.candidate_kinds = base_kinds ? kCandidateCellCentres : 0;
  auto layer = write_layer(base, encode_point_set({}, l.coarse, kQ, models));
  bytes.insert(bytes.end(), layer.begin(), layer.end());
  std::vector<uint8_t> sent;
  const auto section = encode_candidate_section(l.candidates, fresh, sent);
  std::vector<GridPoint> sent_points, rest;
  for (size_t i = 0; i < fresh.size(); ++i) (sent[i] ? sent_points : rest).push_back(fresh[i]);
  std::vector<MortonCode> known = codes_of(l.coarse);
  models.note_points(sent_points);
  merge_known(known, sent_points, kQ);
  LayerHeader fine;
  fine.format_major = kVersionMajor;
  fine.level = 0;
  fine.new_vertices = static_cast<uint32_t>(fresh.size());
  fine.level_vertices = h.vertex_count;
  fine.alpha = 1e9;
  fine.candidate_kinds = kinds;
  layer = write_layer(fine, encode_point_set(known, rest, kQ, models), {}, {}, section);
  bytes.insert(bytes.end(), layer.begin(), layer.end());
  return bytes;
}

TEST(CandidateStream, AHandMadeStreamDecodesToItsPoints) {
  const Layer l = make_layer(5);
  const auto bytes = two_layer_stream(l, l.fresh, kKnownCandidateKinds);
  ProgressiveDecoder dec;
  ASSERT_TRUE(decode_stream(bytes, dec).ok()) << dec.finish().message();
  ASSERT_EQ(dec.points().size(), l.coarse.size() + l.fresh.size());
  const std::vector<GridPoint> layer(dec.points().begin() + static_cast<std::ptrdiff_t>(l.coarse.size()),
                                     dec.points().end());
  EXPECT_EQ(codes_of(layer), codes_of(l.fresh));
  // In Morton order, as a payload gives a layer.
  for (size_t i = 1; i < layer.size(); ++i)
    EXPECT_LT(morton_encode(layer[i - 1], kQ), morton_encode(layer[i], kQ));
}

TEST(CandidateStream, SendingAKnownPointOrCandidatesAtTheBaseIsRefused) {
  // A block of even grid points: the cells' circumcentres are odd points,
  // each beside known ones. A known point given as new is beside a
  // candidate, the section sends it, and the decoder refuses the layer.
  std::vector<GridPoint> block;
  for (const GridPoint& p : test::full_grid(4)) block.push_back({2 * p.x, 2 * p.y, 2 * p.z});
  Layer l = layer_over(block);
  l.fresh = {{3, 3, 3}, {5, 1, 1}};
  std::vector<GridPoint> with_known = l.fresh;
  with_known.push_back({2, 2, 2});
  ProgressiveDecoder dec;
  const Status s = decode_stream(two_layer_stream(l, with_known, kKnownCandidateKinds), dec);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt);
  EXPECT_NE(s.message().find("known"), std::string::npos) << s.message();
  EXPECT_EQ(dec.levels().size(), 1u);  // the base level stands

  const Layer r = make_layer(6);
  ProgressiveDecoder base;
  const Status b = decode_stream(two_layer_stream(r, r.fresh, kKnownCandidateKinds, true), base);
  EXPECT_EQ(b.code(), StatusCode::kCorrupt);
  EXPECT_NE(b.message().find("base level"), std::string::npos) << b.message();
  ProgressiveDecoder unknown;
  EXPECT_EQ(decode_stream(two_layer_stream(r, r.fresh, 4), unknown).code(), StatusCode::kCorrupt);
}

TEST(CandidateStream, ATetGenMeshsFinerLayersUseCandidatesAndDecodeToTheEncodersLevels) {
  const NodeFile node = read_tetgen_node(test::data_path("ellipsoid_793.node"));
  const auto tets =
      read_tetgen_ele(test::data_path("ellipsoid_793.ele"), node.points.size(), node.index_base);
  EncodeInput in;
  in.points = node.points;
  in.tetrahedra = tets;
  EncodeOptions options;
  options.dmax = 3;
  options.cell_hashes = true;
  const auto encoded = encode(in, options);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  EXPECT_EQ(encoded->bytes[8], 7);
  uint64_t sent = 0;
  for (uint64_t n : encoded->report.candidate_points) sent += n;
  EXPECT_GT(sent, 20u);
  ProgressiveDecoder dec;
  size_t levels = 0;
  ASSERT_TRUE(dec.feed(encoded->bytes,
                       [&](const ProgressiveDecoder& d, const DecodedLevel& level) {
                         ++levels;
                         ASSERT_TRUE(level.cell_hash.has_value());
                         EXPECT_EQ(cell_set_hash(d.points(), d.carved_cells()), *level.cell_hash)
                             << level.level;
                       })
                  .ok());
  EXPECT_TRUE(dec.complete());
  EXPECT_GT(levels, 2u);

  // Without candidates (meshenc --no-candidates): the same levels, every
  // point through the set coder, more bytes.
  options.candidates = false;
  const auto plain = encode(in, options);
  ASSERT_TRUE(plain.ok());
  for (uint64_t n : plain->report.candidate_points) EXPECT_EQ(n, 0u);
  EXPECT_GT(plain->bytes.size(), encoded->bytes.size());
  const StreamSummary with = scan_stream(encoded->bytes), without = scan_stream(plain->bytes);
  ASSERT_EQ(with.layers.size(), without.layers.size());
  for (size_t i = 0; i < with.layers.size(); ++i) {
    EXPECT_EQ(with.layers[i].header.cell_hash, without.layers[i].header.cell_hash);
    EXPECT_EQ(without.layers[i].header.candidate_kinds, 0);
  }
  // Only the finest layer uses them.
  for (size_t i = 0; i + 1 < with.layers.size(); ++i) EXPECT_EQ(with.layers[i].header.candidate_kinds, 0);
  EXPECT_NE(with.layers.back().header.candidate_kinds, 0);
}

}  // namespace
}  // namespace dtm
