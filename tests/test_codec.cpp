// The .dtm stream: the point-set coder, the determinism contract (every
// decoded level equals the encoder's), truncation at every byte, damage,
// and incremental feeding.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include "codec/decode.h"
#include "codec/expert_encode.h"
#include "codec/stream/format.h"
#include "codec/stream/format_encoder.h"
#include "codec/stream/layer_coder.h"
#include "core/hierarchy.h"
#include "test_support.h"

namespace dtm {
namespace {

TEST(PointSetCoder, MortonRoundTrip) {
  std::mt19937 rng(1);
  for (int q : {1, 5, 14, 24}) {
    std::uniform_int_distribution<int32_t> c(0, (1 << q) - 1);
    for (int i = 0; i < 200; ++i) {
      const GridPoint p{c(rng), c(rng), c(rng)};
      EXPECT_EQ(morton_decode(morton_encode(p, q), q), p);
    }
  }
}

// Grids up to 21 bits interleave by 64-bit bit spreading: the same codes as
// the definition (spec/FORMAT.md §3.1), bit by bit.
TEST(PointSetCoder, MortonCodesAreTheSpecsBitInterleaving) {
  std::mt19937 rng(2);
  for (int q = 1; q <= 24; ++q) {
    std::uniform_int_distribution<int32_t> c(0, (1 << q) - 1);
    for (int i = 0; i < 100; ++i) {
      const GridPoint p{c(rng), c(rng), c(rng)};
      MortonCode want = 0;
      for (int b = q - 1; b >= 0; --b)
        want = (want << 3) | (((p.x >> b) & 1) << 2) | (((p.y >> b) & 1) << 1) | ((p.z >> b) & 1);
      EXPECT_EQ(morton_encode(p, q), want) << q;
      EXPECT_EQ(morton_decode(want, q), p) << q;
    }
  }
}

// Fresh models of format 3 (reuse = true: lone points may reuse coordinates)
// or of format 2.
SetCoderModels fresh_models(int q, bool reuse) {
  SetCoderModels models;
  if (reuse) models.enable_coordinate_reuse(q);
  return models;
}

// Encodes `pts` as one layer given `known` points, with fresh models.
std::vector<uint8_t> encode_layer(std::span<const GridPoint> pts, int q,
                                  std::span<const GridPoint> known = {}, bool reuse = true) {
  std::vector<MortonCode> codes;
  merge_known(codes, known, q);
  SetCoderModels models = fresh_models(q, reuse);
  return encode_point_set(codes, pts, q, models);
}

Status decode_layer(std::span<const uint8_t> payload, int q, uint32_t count, std::vector<GridPoint>& out,
                    std::span<const GridPoint> known = {}, bool reuse = true) {
  std::vector<MortonCode> codes;
  merge_known(codes, known, q);
  SetCoderModels models = fresh_models(q, reuse);
  return decode_point_set(payload, codes, q, count, models, out);
}

std::vector<GridPoint> sorted(std::vector<GridPoint> v) {
  std::sort(v.begin(), v.end());
  return v;
}

TEST(PointSetCoder, RoundTripsSetsOfAnySize) {
  for (const bool reuse : {false, true})
    for (int q : {1, 3, 10, 14, 21, 22, 24}) {
      for (size_t n : {1, 2, 7, 13, 300}) {
        const size_t cap = q == 1 ? 8 : n;
        const auto pts = test::random_grid_points(std::min(n, cap), q, static_cast<uint32_t>(q * 1000 + n));
        const auto payload = encode_layer(pts, q, {}, reuse);
        std::vector<GridPoint> back;
        ASSERT_TRUE(decode_layer(payload, q, static_cast<uint32_t>(pts.size()), back, {}, reuse).ok());
        EXPECT_EQ(back.size(), pts.size());
        EXPECT_TRUE(std::is_sorted(back.begin(), back.end(), [q](const GridPoint& a, const GridPoint& b) {
          return morton_encode(a, q) < morton_encode(b, q);
        })) << "decoded points come in Morton order";
        EXPECT_EQ(sorted(back), sorted(pts)) << "q=" << q << " n=" << n << " reuse=" << reuse;
      }
    }
}

// Layers coded given the points of earlier layers, with the models carried
// from layer to layer as in a stream: every layer decodes to its points, and
// only with the same known points and the same model history.
TEST(PointSetCoder, LayersRoundTripGivenKnownPointsAndCarriedModels) {
  for (const bool reuse : {false, true}) {
    SCOPED_TRACE(reuse ? "format 3" : "format 2");
    const int q = 12;
    // Random points, a third of them moved onto a few shared planes, so that
    // reused coordinates occur across layers as well as within them.
    auto all = test::random_grid_points(3000, q, 7);
    for (size_t i = 0; i < all.size(); i += 3) all[i].z = 100 * static_cast<int32_t>(i % 7);
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    std::shuffle(all.begin(), all.end(), std::mt19937(3));
    ASSERT_GE(all.size(), 3000u - 20);
    const std::vector<std::span<const GridPoint>> layers = {
        std::span(all).subspan(0, 200), std::span(all).subspan(200, 800), std::span(all).subspan(1000, 2000)};
    std::vector<MortonCode> known;
    SetCoderModels enc_models = fresh_models(q, reuse);
    std::vector<std::vector<uint8_t>> payloads;
    for (const auto& layer : layers) {
      payloads.push_back(encode_point_set(known, layer, q, enc_models));
      merge_known(known, layer, q);
    }
    known.clear();
    SetCoderModels dec_models = fresh_models(q, reuse);
    for (size_t i = 0; i < layers.size(); ++i) {
      std::vector<GridPoint> back;
      ASSERT_TRUE(
          decode_point_set(payloads[i], known, q, static_cast<uint32_t>(layers[i].size()), dec_models, back)
              .ok())
          << "layer " << i;
      EXPECT_EQ(sorted(back), sorted({layers[i].begin(), layers[i].end()})) << "layer " << i;
      merge_known(known, back, q);
    }
    // The last layer with fresh models, or without the known points, is not
    // what was coded: it fails or gives other points.
    std::vector<GridPoint> other;
    const Status fresh = decode_layer(payloads[2], q, 2000, other, std::span(all).first(1000), reuse);
    EXPECT_TRUE(!fresh.ok() || sorted(other) != sorted({layers[2].begin(), layers[2].end()}));
  }
}

// Format 3: a lone point's coordinate that the stream has used before costs
// the rank among the used values in its node's interval, not its raw bits:
// points on a few planes (a layered grid, a torus of rings) code much
// smaller; points in general position cost what they did, within 1%.
TEST(PointSetCoder, ReusedCoordinatesMakeLayeredPointsCheap) {
  const int q = 14;
  std::mt19937 rng(21);
  std::set<GridPoint> on_planes;
  while (on_planes.size() < 4000)
    on_planes.insert({static_cast<int32_t>(rng() % 16384), static_cast<int32_t>(rng() % 16384),
                      static_cast<int32_t>(1000 + 1200 * (rng() % 12))});
  const std::vector<GridPoint> layered(on_planes.begin(), on_planes.end());
  const size_t with = encode_layer(layered, q, {}, true).size(),
               without = encode_layer(layered, q, {}, false).size();
  EXPECT_LT(with, 0.85 * without) << with << " vs " << without;
  const auto general = test::random_grid_points(4000, q, 22);
  const size_t with_g = encode_layer(general, q, {}, true).size();
  const size_t without_g = encode_layer(general, q, {}, false).size();
  EXPECT_LT(with_g, 1.01 * without_g) << with_g << " vs " << without_g;
  std::vector<GridPoint> back;
  ASSERT_TRUE(decode_layer(encode_layer(layered, q), q, static_cast<uint32_t>(layered.size()), back).ok());
  EXPECT_EQ(sorted(back), layered);
}

// The coder follows the coarser level's density: where the known points
// cluster, the new points are, and a layer costs fewer bits when its coarser
// points are known than when coded alone.
TEST(PointSetCoder, KnownPointsMakeALayerCheaper) {
  const int q = 14;
  std::mt19937 rng(11);
  std::set<GridPoint> coarse_set, fine_set;
  for (int cluster = 0; cluster < 60; ++cluster) {
    const GridPoint corner{static_cast<int32_t>(rng() % 16000), static_cast<int32_t>(rng() % 16000),
                           static_cast<int32_t>(rng() % 16000)};
    for (auto* set : {&coarse_set, &fine_set})
      for (int i = 0; i < (set == &coarse_set ? 30 : 10); ++i)
        set->insert({corner.x + static_cast<int32_t>(rng() % 64), corner.y + static_cast<int32_t>(rng() % 64),
                     corner.z + static_cast<int32_t>(rng() % 64)});
  }
  for (const auto& p : coarse_set) fine_set.erase(p);
  const std::vector<GridPoint> coarse(coarse_set.begin(), coarse_set.end());
  const std::vector<GridPoint> fine(fine_set.begin(), fine_set.end());
  const auto alone = encode_layer(fine, q);
  const auto given = encode_layer(fine, q, coarse);
  EXPECT_LT(given.size() * 1.15, alone.size()) << given.size() << " vs " << alone.size();
  std::vector<GridPoint> back;
  ASSERT_TRUE(decode_layer(given, q, static_cast<uint32_t>(fine.size()), back, coarse).ok());
  EXPECT_EQ(sorted(back), fine);
}

TEST(PointSetCoder, RejectsDamagedPayloads) {
  for (const bool reuse : {false, true}) {
    SCOPED_TRACE(reuse ? "format 3" : "format 2");
    const auto pts = test::random_grid_points(50, 8, 3);
    const auto payload = encode_layer(pts, 8, {}, reuse);
    std::vector<GridPoint> out;
    auto extra = payload;
    extra.push_back(0);
    EXPECT_EQ(decode_layer(extra, 8, 50, out, {}, reuse).code(), StatusCode::kCorrupt);  // trailing byte
    for (size_t cut = 0; cut < payload.size(); ++cut) {
      out.clear();
      EXPECT_EQ(decode_layer(std::span(payload).first(cut), 8, 50, out, {}, reuse).code(),
                StatusCode::kCorrupt)
          << "cut at " << cut;
    }
    for (uint32_t count : {0u, 1u, 49u, 51u, 5000u, 1u << 25, 0xFFFFFFFFu}) {  // every count class
      out.clear();
      EXPECT_EQ(decode_layer(payload, 8, count, out, {}, reuse).code(), StatusCode::kCorrupt) << count;
    }
    // Arbitrary bytes never decode to more points than claimed, nor crash.
    std::mt19937 rng(5);
    for (int trial = 0; trial < 2000; ++trial) {
      std::vector<uint8_t> junk(4 + rng() % 40);
      for (auto& b : junk) b = static_cast<uint8_t>(rng());
      out.clear();
      const uint32_t count = 1 + rng() % 100;
      const Status s = decode_layer(junk, 4 + trial % 20, count, out, {}, reuse);
      EXPECT_LE(out.size(), count);
      if (s.ok()) {
        EXPECT_EQ(out.size(), count);
      }
    }
  }
}

// Arbitrary payloads reach each of the coder's structural checks (two points
// in one cell, a point already known, a count out of range) and are refused
// by it: a damaged layer can neither repeat a point nor leave the grid.
TEST(PointSetCoder, JunkPayloadsHitEveryStructuralCheck) {
  for (const bool reuse : {false, true}) {
    SCOPED_TRACE(reuse ? "format 3" : "format 2");
    std::mt19937 rng(9);
    const std::vector<GridPoint> known = {{0, 0, 0}, {1, 1, 1}, {2, 3, 1}, {3, 0, 2}};
    std::map<std::string, int> seen;
    for (int trial = 0; trial < 20000; ++trial) {
      std::vector<uint8_t> junk(4 + rng() % 12);
      for (auto& b : junk) b = static_cast<uint8_t>(rng());
      std::vector<GridPoint> out;
      const uint32_t count = 2 + rng() % 40;
      // A 4^3 grid: collisions are likely.
      const Status s = decode_layer(junk, 2, count, out, known, reuse);
      if (s.ok()) {
        // Whatever decodes is a valid layer: distinct points in the grid, none known.
        std::set<GridPoint> distinct(out.begin(), out.end());
        EXPECT_EQ(distinct.size(), count);
        for (const auto& p : out) {
          EXPECT_TRUE(p.x >= 0 && p.x < 4 && p.y >= 0 && p.y < 4 && p.z >= 0 && p.z < 4);
          EXPECT_EQ(std::count(known.begin(), known.end(), p), 0);
        }
      } else {
        ++seen[s.message()];
      }
    }
    for (const char* check :
         {"two points in one grid cell", "a point of this layer is already in a coarser level",
          "point count out of range"})
      EXPECT_GT(seen[check], 0) << check;
  }
}

TEST(PointSetCoder, RejectsAPointAlreadyKnown) {
  const std::vector<GridPoint> known = {{1, 2, 3}, {7, 7, 7}, {0, 15, 3}};
  const std::vector<GridPoint> layer = {{7, 7, 7}, {9, 9, 9}};
  const auto payload = encode_layer(layer, 4, known);
  std::vector<GridPoint> out;
  const Status s = decode_layer(payload, 4, 2, out, known);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt);
  EXPECT_NE(s.message().find("already in a coarser level"), std::string::npos) << s.message();
}

struct Encoded {
  std::vector<GridPoint> points;
  Hierarchy hierarchy;
  EncodedStream stream;
};

Encoded encode_model(std::vector<GridPoint> points, const Grid& grid, HierarchyOptions opt = {},
                     bool hashes = true) {
  Encoded e;
  e.points = std::move(points);
  e.hierarchy = build_hierarchy(e.points, opt).value();
  StreamOptions eo;
  eo.cell_hashes = hashes;
  e.stream = encode_stream(e.hierarchy, e.points, grid, opt.alpha.kind, eo).value();
  return e;
}

// Every decoded level equals the encoder's: vertex set, Delaunay cells and
// carved cells, compared by coordinates.
void expect_decoder_matches_encoder(const Encoded& e, const std::string& name) {
  ProgressiveDecoder dec;
  int checked = 0;
  const auto& levels = e.hierarchy.levels;
  const Status s = dec.feed(e.stream.bytes, [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
    const Level& ref = levels[l.level];
    std::vector<GridPoint> want;
    for (uint32_t i : ref.vertices) want.push_back(e.points[i]);
    std::vector<GridPoint> got = d.points();
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, want) << name << " level " << l.level;
    EXPECT_EQ(l.alpha, ref.alpha);
    const TetMesh dt = d.delaunay();
    EXPECT_EQ(test::cells_by_coords(dt, d.points()),
              test::cells_by_coords(delaunay_tetrahedralize(want).value(), want))
        << name << " level " << l.level;
    TetMesh carved_ref, carved_dec;
    carved_ref.cells = ref.carved_cells();
    carved_dec.cells = d.carved_cells();
    EXPECT_EQ(test::cells_by_coords(carved_dec, d.points()), test::cells_by_coords(carved_ref, e.points))
        << name << " level " << l.level;
    ASSERT_TRUE(l.cell_hash.has_value());
    EXPECT_EQ(*l.cell_hash, cell_set_hash(d.points(), carved_dec.cells));
    ++checked;
  });
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_TRUE(dec.finish().ok());
  EXPECT_EQ(checked, static_cast<int>(levels.size()));
}

class CorpusCodec : public ::testing::TestWithParam<std::string> {};

TEST_P(CorpusCodec, DecodedLevelsEqualTheEncodersAndStreamsAreReproducible) {
  const auto q = test::load_quantized(GetParam());
  HierarchyOptions opt;
  opt.dmax = 2.0 * ((1 << 14) - 1) / 256;  // Dmax = 2 in a 256-unit box
  const Encoded e = encode_model(q.points, q.grid, opt);
  expect_decoder_matches_encoder(e, GetParam());
  EXPECT_EQ(encode_model(q.points, q.grid, opt).stream.bytes, e.stream.bytes);
}

INSTANTIATE_TEST_SUITE_P(Corpus, CorpusCodec, ::testing::ValuesIn(test::kCorpus),
                         [](const auto& info) { return info.param; });

TEST(Codec, Bunny100kRoundTrips) {
  const auto q = test::load_quantized("bunny_100k");
  HierarchyOptions opt;
  opt.dmax = 2.0 * ((1 << 14) - 1) / 256;
  opt.measure_boundary_error = false;
  expect_decoder_matches_encoder(encode_model(q.points, q.grid, opt), "bunny_100k");
}

TEST(Codec, DegenerateGridsRoundTrip) {
  Grid grid;
  grid.qbits = 5;
  HierarchyOptions opt;
  opt.dmax = 0.5;
  opt.stop_when_boundary_is_final = false;
  expect_decoder_matches_encoder(encode_model(test::full_grid(10), grid, opt), "full_grid_10");
  expect_decoder_matches_encoder(encode_model(test::random_grid_points(2000, 5, 9), grid, opt),
                                 "random_5bit");
  AlphaPolicy hull{AlphaPolicy::Kind::kConvexHull, 0};
  opt.alpha = hull;
  expect_decoder_matches_encoder(encode_model(test::full_grid(8), grid, opt), "full_grid_8_hull");
}

Encoded small_stream() {
  const auto q = test::load_quantized("torus_288");
  HierarchyOptions opt;
  opt.dmax = 335;
  return encode_model(q.points, q.grid, opt);
}

// Layer ends: the byte offsets at which each level becomes complete.
std::vector<size_t> layer_ends(const EncodedStream& s) {
  std::vector<size_t> ends;
  size_t at = kHeaderSize;
  for (size_t l = s.layer_bytes.size(); l-- > 0;) ends.push_back(at += s.layer_bytes[l]);
  return ends;
}

TEST(Codec, EveryPrefixDecodesToTheWholeLayersItHolds) {
  const Encoded e = small_stream();
  const auto ends = layer_ends(e.stream);
  ASSERT_EQ(ends.back(), e.stream.bytes.size());
  for (size_t len = 0; len <= e.stream.bytes.size(); ++len) {
    ProgressiveDecoder dec;
    ASSERT_TRUE(dec.feed(std::span(e.stream.bytes).first(len)).ok()) << "prefix " << len;
    const size_t whole = std::upper_bound(ends.begin(), ends.end(), len) - ends.begin();
    ASSERT_EQ(dec.levels().size(), whole) << "prefix " << len;
    const Status fin = dec.finish();
    if (len == e.stream.bytes.size()) {
      EXPECT_TRUE(fin.ok());
    } else {
      EXPECT_EQ(fin.code(), StatusCode::kTruncated) << "prefix " << len;
    }
    if (whole > 0) {
      const int level = dec.finest_level();
      EXPECT_EQ(dec.points().size(), e.hierarchy.levels[level].vertices.size());
    }
    const StreamSummary summary = scan_stream(std::span(e.stream.bytes).first(len));
    EXPECT_EQ(summary.status.ok(), len == e.stream.bytes.size());
    if (!summary.status.ok()) {
      EXPECT_EQ(summary.status.code(), StatusCode::kTruncated) << len;
    }
  }
}

TEST(Codec, FeedingInRandomChunksGivesTheSameLevels) {
  const Encoded e = small_stream();
  std::mt19937 rng(4);
  for (int trial = 0; trial < 20; ++trial) {
    ProgressiveDecoder dec;
    std::vector<int> seen;
    size_t at = 0;
    while (at < e.stream.bytes.size()) {
      const size_t n =
          std::min<size_t>(std::uniform_int_distribution<size_t>(0, 300)(rng), e.stream.bytes.size() - at);
      ASSERT_TRUE(dec.feed(std::span(e.stream.bytes).subspan(at, n),
                           [&](const ProgressiveDecoder&, const DecodedLevel& l) { seen.push_back(l.level); })
                      .ok());
      at += n;
    }
    EXPECT_TRUE(dec.finish().ok());
    ASSERT_EQ(seen.size(), e.hierarchy.levels.size());
    for (size_t i = 0; i < seen.size(); ++i)
      EXPECT_EQ(seen[i], static_cast<int>(e.hierarchy.levels.size() - 1 - i));
  }
}

TEST(Codec, ADamagedLayerIsReportedAndTheLevelsBeforeItStay) {
  const Encoded e = small_stream();
  const auto ends = layer_ends(e.stream);
  for (size_t k = 0; k < ends.size(); ++k) {
    auto bytes = e.stream.bytes;
    const size_t start = k == 0 ? kHeaderSize : ends[k - 1];
    bytes[start + kLayerHeaderSize + 1 < ends[k] ? start + kLayerHeaderSize + 1 : start + 3] ^= 0x10;
    ProgressiveDecoder dec;
    const Status s = dec.feed(bytes);
    ASSERT_EQ(s.code(), StatusCode::kCorrupt) << "layer " << k;
    const int level = static_cast<int>(e.hierarchy.levels.size() - 1 - k);
    EXPECT_NE(s.message().find("level " + std::to_string(level) + " at byte " + std::to_string(start)),
              std::string::npos)
        << s.message();
    EXPECT_EQ(dec.levels().size(), k);
    EXPECT_EQ(dec.finish().code(), StatusCode::kCorrupt);
  }
}

TEST(Codec, ForeignAndFutureStreamsAreRejected) {
  const Encoded e = small_stream();
  auto bytes = e.stream.bytes;
  bytes[1] = 'X';
  ProgressiveDecoder a;
  EXPECT_EQ(a.feed(bytes).code(), StatusCode::kNotDtm);

  bytes = e.stream.bytes;
  bytes[8] = kVersionMajor + 1;  // a future version: refused before the checksum is looked at
  ProgressiveDecoder b;
  EXPECT_EQ(b.feed(bytes).code(), StatusCode::kUnsupported);

  bytes = e.stream.bytes;
  bytes[20] ^= 1;  // origin: header checksum
  ProgressiveDecoder c;
  EXPECT_EQ(c.feed(bytes).code(), StatusCode::kCorrupt);

  bytes = e.stream.bytes;
  bytes.push_back(0);  // trailing garbage
  ProgressiveDecoder d;
  const Status trailing = d.feed(bytes);
  EXPECT_EQ(trailing.code(), StatusCode::kCorrupt);
  // (Where the stream ends, not how many bytes follow: they may arrive in
  // pieces.)
  EXPECT_NE(trailing.message().find("ends at byte " + std::to_string(e.stream.bytes.size())),
            std::string::npos)
      << trailing.message();
  EXPECT_EQ(scan_stream(bytes).status.code(), StatusCode::kCorrupt);
}

TEST(Codec, TrailingDataIsRejectedEvenInALaterFeed) {
  const Encoded e = small_stream();
  ProgressiveDecoder dec;
  ASSERT_TRUE(dec.feed(e.stream.bytes).ok());
  EXPECT_TRUE(dec.complete());
  EXPECT_TRUE(dec.finish().ok());
  const uint8_t junk[] = {1, 2, 3};
  EXPECT_EQ(dec.feed(junk).code(), StatusCode::kCorrupt);
  EXPECT_EQ(dec.finish().code(), StatusCode::kCorrupt);
}

// A layer whose checksum is right but whose content is not: built with the
// format's own writer, so only the decoder's semantic checks can catch it.
TEST(Codec, ALayerRepeatingACoarserPointIsRejected) {
  StreamHeader h;
  h.grid.qbits = 4;
  h.level_count = 2;
  h.vertex_count = 6;
  const std::vector<GridPoint> base = {{0, 0, 0}, {9, 0, 0}, {0, 9, 0}, {0, 0, 9}, {5, 5, 5}};
  LayerHeader l1;
  l1.level = 1;
  l1.new_vertices = 5;
  l1.level_vertices = 5;
  l1.alpha = 100;
  LayerHeader l0 = l1;
  l0.level = 0;
  l0.new_vertices = 1;
  l0.level_vertices = 6;
  auto bytes = write_header(h);
  std::vector<MortonCode> known;
  SetCoderModels models;  // as the stream's format (3) has them
  models.enable_coordinate_reuse(4);
  const auto base_payload = encode_point_set(known, base, 4, models);
  merge_known(known, base, 4);
  const auto repeat_payload = encode_point_set(known, std::vector<GridPoint>{{9, 0, 0}}, 4, models);
  for (const auto& part : {write_layer(l1, base_payload), write_layer(l0, repeat_payload)})
    bytes.insert(bytes.end(), part.begin(), part.end());
  ProgressiveDecoder dec;
  const Status s = dec.feed(bytes);
  EXPECT_EQ(s.code(), StatusCode::kCorrupt);
  EXPECT_NE(s.message().find("already in a coarser level"), std::string::npos) << s.message();
  EXPECT_EQ(dec.levels().size(), 1u);  // the base level stands
}

TEST(Codec, AFlatBaseLevelIsRejected) {
  StreamHeader h;
  h.grid.qbits = 4;
  h.level_count = 1;
  h.vertex_count = 4;
  LayerHeader l;
  l.level = 0;
  l.new_vertices = 4;
  l.level_vertices = 4;
  l.alpha = 100;
  auto bytes = write_header(h);
  const auto layer =
      write_layer(l, encode_layer(std::vector<GridPoint>{{0, 0, 1}, {5, 0, 1}, {0, 5, 1}, {5, 5, 1}}, 4));
  bytes.insert(bytes.end(), layer.begin(), layer.end());
  ProgressiveDecoder dec;
  EXPECT_EQ(dec.feed(bytes).code(), StatusCode::kCorrupt);
}

TEST(Codec, VertexLimitIsEnforcedBeforeDecoding) {
  const Encoded e = small_stream();
  DecoderOptions o;
  o.max_vertices = 100;
  ProgressiveDecoder dec(o);
  const Status s = dec.feed(e.stream.bytes);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded) << s.message();
}

TEST(Codec, ALevelAskedForOnlyAtTheEndIsTheSameMesh) {
  // Without callbacks the points go into the triangulation in one batch at
  // the end (the fast path); the mesh must be the one built layer by layer.
  const Encoded e = small_stream();
  for (int stop : {-1, 3}) {
    DecoderOptions o;
    o.stop_after_level = stop;
    ProgressiveDecoder lazy(o), eager(o);
    ASSERT_TRUE(lazy.feed(e.stream.bytes).ok());
    ASSERT_TRUE(
        eager.feed(e.stream.bytes, [](const ProgressiveDecoder& d, const DecodedLevel&) { d.delaunay(); })
            .ok());
    EXPECT_EQ(test::cells_by_coords(lazy.delaunay(), lazy.points()),
              test::cells_by_coords(eager.delaunay(), eager.points()));
    TetMesh a, b;
    a.cells = lazy.carved_cells();
    b.cells = eager.carved_cells();
    EXPECT_EQ(test::cells_by_coords(a, lazy.points()), test::cells_by_coords(b, eager.points()));
    EXPECT_FALSE(a.cells.empty());
  }
}

TEST(Codec, StopsAtTheRequestedLevel) {
  const Encoded e = small_stream();
  DecoderOptions o;
  o.stop_after_level = 2;
  ProgressiveDecoder dec(o);
  EXPECT_TRUE(decode_stream(e.stream.bytes, dec).ok());
  EXPECT_EQ(dec.finest_level(), 2);
  EXPECT_EQ(dec.points().size(), e.hierarchy.levels[2].vertices.size());
}

// A level the stream does not have is refused once the header is read: a
// caller learns it from the first bytes, not after decoding every level.
TEST(Codec, ALevelTheStreamLacksIsRefusedAtTheHeader) {
  const Encoded e = small_stream();
  const int levels = static_cast<int>(e.hierarchy.levels.size());
  for (int stop : {levels, levels + 5, -2}) {
    DecoderOptions o;
    o.stop_after_level = stop;
    ProgressiveDecoder dec(o);
    const Status s = dec.feed(std::span(e.stream.bytes).first(kHeaderSize));
    EXPECT_EQ(s.code(), StatusCode::kInvalidInput) << stop;
    EXPECT_EQ(s.message(), "level " + std::to_string(stop) + " asked, the stream has levels 0 to " +
                               std::to_string(levels - 1));
    EXPECT_FALSE(dec.feed(e.stream.bytes).ok()) << "the error stands";
    EXPECT_EQ(dec.finest_level(), -1);
  }
  DecoderOptions coarsest;
  coarsest.stop_after_level = levels - 1;
  ProgressiveDecoder dec(coarsest);
  EXPECT_TRUE(decode_stream(e.stream.bytes, dec).ok());
  EXPECT_EQ(dec.finest_level(), levels - 1);
}

}  // namespace
}  // namespace dtm
