// Regions (materials) on every level (spec/FORMAT.md §2.2, §3.6;
// spec/HIERARCHY.md §2.2): every decoded level's cells carry the region of
// the input tetrahedra that hold their centroids, found here by a search of
// the input's own tetrahedra (not the encoder's solids); level 0's input
// cells keep their labels; damaged region tables and sections are refused,
// truncated streams end cleanly; the readers take gmsh's, Medit's and
// TetGen's labels and the writers give them back.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <thread>
#include <vector>

#include "codec/decode.h"
#include "codec/encode.h"
#include "codec/region_decode.h"
#include "codec/sections/face_coder.h"
#include "codec/sections/region_coder.h"
#include "codec/stream/format.h"
#include "codec/stream/format_encoder.h"
#include "core/quantize.h"
#include "core/reference_shape.h"
#include "mesh/carving.h"
#include "mesh/delaunay.h"
#include "mesh/predicates.h"
#include "mesh/topology.h"
#include "test_support.h"
#include "thread_ranks.h"
#include "tools/decoded_mesh.h"
#include "tools/formats/input.h"
#include "tools/formats/mesh_writers.h"

namespace dtm {
namespace {

using Tet = std::array<uint32_t, 4>;
using P4 = std::array<int64_t, 3>;

// A three-material block: random points, their Delaunay tetrahedra as the
// input's cells, each labelled by its centroid: 7 in a ball, -2 on one side
// of a plane, 3 elsewhere. Curved and flat interfaces, a region that is not
// convex.
struct RegionInput {
  std::vector<InputPoint> points;
  std::vector<Tet> tets;
  std::vector<int32_t> labels;
};

RegionInput three_materials(size_t count, uint32_t seed) {
  RegionInput in;
  const std::vector<GridPoint> g = test::random_grid_points(count, 10, seed);
  for (const GridPoint& p : g) in.points.push_back({double(p.x), double(p.y), double(p.z)});
  const TetMesh dt = delaunay_tetrahedralize(g).value();
  for (const Tet& t : dt.cells) {
    double c[3] = {0, 0, 0};
    for (uint32_t v : t) c[0] += g[v].x / 4.0, c[1] += g[v].y / 4.0, c[2] += g[v].z / 4.0;
    const double r2 = (c[0] - 500) * (c[0] - 500) + (c[1] - 520) * (c[1] - 520) + (c[2] - 480) * (c[2] - 480);
    in.tets.push_back(t);
    in.labels.push_back(r2 < 280.0 * 280.0 ? 7 : c[0] > 700 ? -2 : 3);
  }
  return in;
}

// Exact orientation of (a, b, c, d) at four times the grid scale.
int orientation(const P4& a, const P4& b, const P4& c, const P4& d) {
  const __int128 bx = b[0] - a[0], by = b[1] - a[1], bz = b[2] - a[2];
  const __int128 cx = c[0] - a[0], cy = c[1] - a[1], cz = c[2] - a[2];
  const __int128 dx = d[0] - a[0], dy = d[1] - a[1], dz = d[2] - a[2];
  const __int128 det = bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx);
  return det > 0 ? 1 : det < 0 ? -1 : 0;
}

// Which input tetrahedra hold a point (closed), by a bucket grid over
// their boxes: the label of the first region (ascending labels) holding it,
// or nullopt outside them all.
class RegionLocator {
 public:
  RegionLocator(const std::vector<GridPoint>& points, const std::vector<Tet>& tets,
                const std::vector<int32_t>& labels)
      : labels_(labels) {
    for (const GridPoint& p : points)
      corners_.push_back({4 * int64_t{p.x}, 4 * int64_t{p.y}, 4 * int64_t{p.z}});
    for (const Tet& t : tets) tets_.push_back(t);
    for (const P4& p : corners_)
      for (int k = 0; k < 3; ++k) hi_ = std::max(hi_, p[static_cast<size_t>(k)]);
    cell_ = hi_ / kCells + 1;
    buckets_.resize(kCells * kCells * kCells);
    for (uint32_t i = 0; i < tets_.size(); ++i) {
      P4 lo{INT64_MAX, INT64_MAX, INT64_MAX}, hi{0, 0, 0};
      for (uint32_t v : tets_[i])
        for (size_t k = 0; k < 3; ++k)
          lo[k] = std::min(lo[k], corners_[v][k]), hi[k] = std::max(hi[k], corners_[v][k]);
      for (int64_t x = lo[0] / cell_; x <= hi[0] / cell_; ++x)
        for (int64_t y = lo[1] / cell_; y <= hi[1] / cell_; ++y)
          for (int64_t z = lo[2] / cell_; z <= hi[2] / cell_; ++z) buckets_[index(x, y, z)].push_back(i);
    }
  }
  std::optional<int32_t> label(const P4& p) const {
    std::optional<int32_t> best;
    for (uint32_t i : buckets_[index(p[0] / cell_, p[1] / cell_, p[2] / cell_)]) {
      const Tet& t = tets_[i];
      const P4 &a = corners_[t[0]], &b = corners_[t[1]], &c = corners_[t[2]], &d = corners_[t[3]];
      const int o = orientation(a, b, c, d);
      if (o == 0) continue;
      if (orientation(p, b, c, d) * o < 0 || orientation(a, p, c, d) * o < 0 ||
          orientation(a, b, p, d) * o < 0 || orientation(a, b, c, p) * o < 0)
        continue;
      if (!best || labels_[i] < *best) best = labels_[i];
    }
    return best;
  }

 private:
  static constexpr int64_t kCells = 24;
  size_t index(int64_t x, int64_t y, int64_t z) const {
    return static_cast<size_t>((std::min(x, kCells - 1) * kCells + std::min(y, kCells - 1)) * kCells +
                               std::min(z, kCells - 1));
  }
  std::vector<P4> corners_;
  std::vector<Tet> tets_;
  const std::vector<int32_t>& labels_;
  int64_t hi_ = 0, cell_ = 1;
  std::vector<std::vector<uint32_t>> buckets_;
};

// Bricks of 64 points, levels built in blocks of `block_points`: many
// chunks and seams for a few thousand points.
EncodeOptions small_bricks(uint64_t block_points) {
  EncodeOptions options;
  options.bricks = true;
  options.brick_points = 64;
  options.block_points = block_points;
  return options;
}

struct Encoded {
  std::vector<uint8_t> bytes;
  EncodeReport report;
};

Encoded encode_regions(const RegionInput& in, std::map<int32_t, std::string> names = {},
                       EncodeOptions options = {}) {
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.tetrahedron_regions = in.labels;
  input.region_names = std::move(names);
  options.dmax = 8;
  auto encoded = encode(input, options);
  EXPECT_TRUE(encoded.ok()) << encoded.status().message();
  if (!encoded.ok()) return {};
  return {encoded->bytes, encoded->report};
}

// Every decoded level's cells carry the region of the input tetrahedra
// holding their centroids (all three materials on every level), level 0's
// input cells their own labels, and every level is within D_max of the
// interfaces.
void expect_regions_of_centroids(const RegionInput& in, const Encoded& e) {
  // The input's tetrahedra on the grid, labels alongside (the encoder's
  // own plan: the same grid).
  const QuantizedPoints q = quantize(in.points, 14).value();
  std::vector<Tet> tets = in.tets;
  std::vector<int32_t> labels = in.labels;
  grid_tetrahedra_in_place(tets, q, &labels);
  const RegionLocator locate(q.points, tets, labels);
  std::set<std::array<GridPoint, 4>> input_cells;
  std::map<std::array<GridPoint, 4>, int32_t> input_label;
  for (size_t i = 0; i < tets.size(); ++i) {
    std::array<GridPoint, 4> k = {q.points[tets[i][0]], q.points[tets[i][1]], q.points[tets[i][2]],
                                  q.points[tets[i][3]]};
    std::sort(k.begin(), k.end());
    input_label[k] = labels[i];
  }

  ProgressiveDecoder decoder;
  int levels = 0;
  uint64_t input_cells_checked = 0;
  ASSERT_TRUE(decoder
                  .feed(e.bytes,
                        [&](const ProgressiveDecoder& d, const DecodedLevel& level) {
                          ++levels;
                          ASSERT_EQ(d.regions().size(), 3u);
                          const TetMesh dt = d.delaunay();
                          std::vector<uint32_t> order;
                          const std::vector<uint8_t> region = d.carving(dt, order);
                          ASSERT_TRUE(d.mesh_status().ok()) << d.mesh_status().message();
                          std::map<int32_t, uint64_t> seen;
                          for (size_t c = 0; c < dt.cells.size(); ++c) {
                            P4 centroid{0, 0, 0};
                            std::array<GridPoint, 4> k;
                            for (int i = 0; i < 4; ++i) {
                              const GridPoint& p = d.points()[dt.cells[c][static_cast<size_t>(i)]];
                              centroid[0] += p.x, centroid[1] += p.y, centroid[2] += p.z;
                              k[static_cast<size_t>(i)] = p;
                            }
                            const std::optional<int32_t> expected = locate.label(centroid);
                            // (A bricked level keeps no cell above its kept radius.)
                            if (!region[c] && expected &&
                                carving_radius(d.points(), dt.cells[c]) > level.kept_radius)
                              continue;
                            ASSERT_EQ(region[c] != 0, expected.has_value()) << "level " << level.level;
                            if (!expected) continue;
                            const int32_t got = d.regions()[region[c] - 1u].label;
                            ASSERT_EQ(got, *expected) << "level " << level.level << " cell " << c;
                            ++seen[got];
                            if (level.level == 0) {
                              std::sort(k.begin(), k.end());
                              const auto it = input_label.find(k);
                              if (it != input_label.end()) {
                                EXPECT_EQ(got, it->second);
                                ++input_cells_checked;
                              }
                            }
                          }
                          // Every level keeps all three materials.
                          EXPECT_EQ(seen.size(), 3u) << "level " << level.level;
                        })
                  .ok());
  EXPECT_TRUE(decoder.finish().ok());
  EXPECT_EQ(levels, static_cast<int>(e.report.levels.size()));
  EXPECT_GT(input_cells_checked, tets.size() * 8 / 10);
  // The interfaces are measured as the boundary is: every level within D_max.
  for (const LevelReport& l : e.report.levels) {
    ASSERT_TRUE(l.reference_error.has_value());
    EXPECT_LE(l.reference_error->max, 8 / e.report.grid.step * (1 + 1e-9));
  }
}

TEST(Regions, EveryLevelsCellsTakeTheRegionHoldingTheirCentroids) {
  const RegionInput in = three_materials(2500, 11);
  const Encoded e = encode_regions(in, {{7, "steel"}});
  ASSERT_FALSE(e.bytes.empty());
  ASSERT_EQ(e.report.regions.size(), 3u);
  EXPECT_EQ(e.report.regions[0].label, -2);
  EXPECT_EQ(e.report.regions[2].label, 7);
  EXPECT_EQ(e.report.regions[2].name, "steel");
  ASSERT_GE(e.report.levels.size(), 3u) << "too few levels to test coarse ones";

  expect_regions_of_centroids(in, e);
}

// A bricked stream (15.0) on one process: each chunk carries its kept
// cells' regions, decoded whole, by region and in pieces alike.
TEST(Regions, BrickedLevelsCarryThemInEveryChunk) {
  const RegionInput in = three_materials(2500, 11);
  EncodeOptions options = small_bricks(600);
  const Encoded e = encode_regions(in, {{7, "steel"}}, options);
  ASSERT_FALSE(e.bytes.empty());
  EXPECT_EQ(e.bytes[8], kVersionMajorBrickedRegions);
  // A bricked stream of regions from before 15.0 is refused.
  StreamHeader h;
  ASSERT_TRUE(parse_header(e.bytes, h).ok());
  EXPECT_TRUE((h.flags & kFlagBricks) && (h.flags & kFlagRegions));
  h.version_major = kVersionMajorBrickedRegions - 1;
  EXPECT_EQ(parse_header(write_header(h), h).code(), StatusCode::kCorrupt);
  ASSERT_EQ(e.report.regions.size(), 3u);
  ASSERT_GE(e.report.levels.size(), 3u) << "too few levels to test coarse ones";
  expect_regions_of_centroids(in, e);

  // The region reader's cells (pieces of each level, a box) have the whole
  // decoder's regions.
  for (int level = 0; level < 2; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    DecoderOptions stop;
    stop.stop_after_level = level;
    ProgressiveDecoder whole(stop);
    ASSERT_TRUE(whole.feed(e.bytes).ok());
    const ProgressiveDecoder::LevelCells cells = whole.level_cells();
    ASSERT_TRUE(whole.mesh_status().ok()) << whole.mesh_status().message();
    std::map<std::array<GridPoint, 4>, uint8_t> region_of;
    for (uint32_t c : cells.order)
      if (cells.kept[c]) {
        std::array<GridPoint, 4> k;
        for (int i = 0; i < 4; ++i)
          k[static_cast<size_t>(i)] = whole.points()[cells.mesh.cells[c][static_cast<size_t>(i)]];
        std::sort(k.begin(), k.end());
        region_of[k] = cells.kept[c];
      }
    MemorySource source(e.bytes);
    size_t in_pieces = 0;
    for (int piece = 0; piece < 3; ++piece) {
      const auto got = decode_piece(source, level, piece, 3);
      ASSERT_TRUE(got.ok()) << got.status().message();
      ASSERT_EQ(got->cell_regions.size(), got->cells.size());
      ASSERT_EQ(got->regions.size(), 3u);
      for (size_t c = 0; c < got->cells.size(); ++c) {
        std::array<GridPoint, 4> k;
        for (int i = 0; i < 4; ++i)
          k[static_cast<size_t>(i)] = got->points[got->cells[c][static_cast<size_t>(i)]];
        std::sort(k.begin(), k.end());
        const auto it = region_of.find(k);
        ASSERT_NE(it, region_of.end());
        EXPECT_EQ(got->cell_regions[c], it->second);
      }
      in_pieces += got->cells.size();
    }
    EXPECT_EQ(in_pieces, region_of.size());
  }
}

TEST(Regions, OneRegionStillNamesItsLabelAndCostsNoSection) {
  RegionInput in = three_materials(800, 5);
  std::fill(in.labels.begin(), in.labels.end(), 42);
  const Encoded e = encode_regions(in, {{42, "rock"}});
  ASSERT_EQ(e.report.regions.size(), 1u);
  for (uint64_t b : e.report.region_bytes) EXPECT_EQ(b, 0u);
  ProgressiveDecoder decoder;
  ASSERT_TRUE(decode_stream(e.bytes, decoder).ok());
  const OutputMesh mesh = decoded_mesh(decoder, "one region");
  ASSERT_EQ(mesh.region.size(), mesh.cells.size());
  for (int32_t r : mesh.region) EXPECT_EQ(r, 42);
  EXPECT_EQ(mesh.region_names.at(42), "rock");
}

TEST(Regions, WithoutRegionsTheStreamIsAsBefore) {
  RegionInput in = three_materials(800, 5);
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  EncodeOptions options;
  options.dmax = 8;
  const auto plain = encode(input, options).value();
  EXPECT_EQ(plain.bytes[8], kVersionMajorUnbricked);
  ProgressiveDecoder decoder;
  ASSERT_TRUE(decode_stream(plain.bytes, decoder).ok());
  EXPECT_TRUE(decoder.regions().empty());
  EXPECT_TRUE(decoded_mesh(decoder, "plain").region.empty());
}

// The ranks of a run hold the reference in parts, a region at a time, and
// a block's work asks the ranks which region holds what its parts do not
// know: one process, or 2 or 3 ranks answering while they work or in
// their exchanges, write the same bytes.
TEST(Regions, BrickedStreamsAreTheSameBytesOnAnyNumberOfRanks) {
  const RegionInput in = three_materials(2500, 11);
  EncodeOptions options = small_bricks(600);
  options.cell_hashes = true;
  const std::map<int32_t, std::string> names = {{7, "steel"}};
  const Encoded alone = encode_regions(in, names, options);
  ASSERT_FALSE(alone.bytes.empty());
  ASSERT_EQ(alone.report.regions.size(), 3u);
  uint64_t asked = 0;
  for (const bool at_once : {true, false}) {
    for (int ranks : {2, 3}) {
      SCOPED_TRACE(std::to_string(ranks) + (at_once ? " ranks answering while they work" : " ranks"));
      const std::vector<Encoded> made = test::on_ranks(ranks, at_once, [&](RankExchange& rank, int) {
        EncodeOptions on_rank = options;
        on_rank.exchange = &rank;
        return encode_regions(in, names, on_rank);
      });
      for (const Encoded& e : made) EXPECT_TRUE(e.bytes == alone.bytes);
      asked += made[0].report.reference_questions + made[0].report.reference_questions_at_once;
    }
  }
  // (The ranks' answers were needed: else the test shows nothing of them.)
  EXPECT_GT(asked, 0u);
}

TEST(Regions, RefusedWhereTheStreamCannotCarryThem) {
  RegionInput in = three_materials(400, 3);
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.tetrahedron_regions = in.labels;
  EXPECT_EQ(encode(input, EncodeOptions::paper()).status().code(), StatusCode::kInvalidInput);
  std::vector<int32_t> short_labels(in.labels.begin(), in.labels.end() - 1);
  input.tetrahedron_regions = short_labels;
  EXPECT_EQ(encode(input, EncodeOptions{}).status().code(), StatusCode::kInvalidInput);
  std::vector<int32_t> many(in.labels.size());
  for (size_t i = 0; i < many.size(); ++i) many[i] = static_cast<int32_t>(i % 300);
  input.tetrahedron_regions = many;
  EXPECT_EQ(encode(input, EncodeOptions{}).status().code(), StatusCode::kInvalidInput);
  // A name of a label no tetrahedron has would be lost: refused, naming it.
  input.tetrahedron_regions = in.labels;
  input.region_names = {{7, "kept"}, {8, "nothing"}};
  const auto named = encode(input, EncodeOptions{});
  EXPECT_EQ(named.status().code(), StatusCode::kInvalidInput);
  EXPECT_NE(named.status().message().find("region 8"), std::string::npos) << named.status().message();
  input.region_names = {{7, "kept"}};
  EXPECT_TRUE(encode(input, EncodeOptions{}).ok());
  input.tetrahedron_regions = {};
  EXPECT_EQ(encode(input, EncodeOptions{}).status().code(), StatusCode::kInvalidInput);
}

// Every prefix decodes to whole levels or stops as truncated; every bit
// flipped in the region table is caught (its checksum, or the layers').
TEST(Regions, TruncatedAndDamagedStreamsEndCleanly) {
  const RegionInput in = three_materials(600, 9);
  const Encoded e = encode_regions(in, {{3, "a"}, {7, "b"}});
  ASSERT_FALSE(e.bytes.empty());
  for (size_t len = 0; len < e.bytes.size(); len += (len < 200 ? 1 : 37)) {
    ProgressiveDecoder d;
    const Status fed = d.feed(std::span(e.bytes).first(len));
    ASSERT_TRUE(fed.ok()) << len << ": " << fed.message();
    EXPECT_EQ(d.finish().code(), StatusCode::kTruncated) << len;
    if (d.finest_level() >= 0) {
      const OutputMesh m = decoded_mesh(d, "prefix");
      EXPECT_EQ(m.region.size(), m.cells.size());
    }
  }
  const size_t table_end = kHeaderSize + e.report.region_table_bytes;
  for (size_t byte = kHeaderSize; byte < table_end; ++byte)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> damaged = e.bytes;
      damaged[byte] ^= static_cast<uint8_t>(1 << bit);
      ProgressiveDecoder d;
      const Status s = d.feed(damaged);
      EXPECT_TRUE(!s.ok() || !d.finish().ok()) << "byte " << byte << " bit " << bit;
    }
}

// Below the checksums: a damaged region section is refused or decodes to
// regions in the table, never out of it.
TEST(Regions, DamagedSectionsGiveRegionsInTheTableOrAnError) {
  const std::vector<GridPoint> g = test::random_grid_points(400, 8, 2);
  const TetMesh dt = delaunay_tetrahedralize(g).value();
  const std::vector<uint32_t> order = canonical_cell_order(dt.cells);
  std::vector<uint8_t> region(dt.cells.size());
  std::mt19937 rng(4);
  for (size_t c = 0; c < region.size(); ++c) region[c] = (g[dt.cells[c][0]].x < 128) ? 1 : 2 + rng() % 3;
  const std::vector<uint8_t> section = encode_regions(dt, order, region, 4);
  std::vector<uint8_t> decoded(dt.cells.size(), 1);
  ASSERT_TRUE(decode_regions(section, dt, order, 4, decoded).ok());
  EXPECT_EQ(decoded, region);
  int refused = 0;
  for (size_t byte = 0; byte < section.size(); ++byte)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> damaged = section;
      damaged[byte] ^= static_cast<uint8_t>(1 << bit);
      std::vector<uint8_t> out(dt.cells.size(), 1);
      const Status s = decode_regions(damaged, dt, order, 4, out);
      if (!s.ok()) {
        EXPECT_EQ(s.code(), StatusCode::kCorrupt);
        ++refused;
        continue;
      }
      for (uint8_t r : out) EXPECT_TRUE(r >= 1 && r <= 4);
    }
  EXPECT_GT(refused, 0);
  for (size_t len = 0; len < section.size(); ++len) {
    std::vector<uint8_t> out(dt.cells.size(), 1);
    EXPECT_EQ(decode_regions(std::span(section).first(len), dt, order, 4, out).code(), StatusCode::kCorrupt)
        << len;
  }
  std::vector<uint8_t> out(dt.cells.size(), 1);
  EXPECT_EQ(decode_regions(section, dt, order, 1, out).code(), StatusCode::kCorrupt);
}

// Each chunk's section of a bricked layer damaged bit by bit, then cut
// short, the others whole: `decode(sections, out)` refuses (kCorrupt,
// naming the chunk) or gives `out`, of which `check(chunk, out)` must hold;
// some flips are refused, and every cut is (but a cut to nothing where
// `empty_decodes`: then it decodes).
template <class Decode, class Check>
void expect_chunk_damage_refused_or_checked(const std::vector<std::vector<uint8_t>>& sections,
                                            const Decode& decode, const Check& check, bool empty_decodes) {
  std::vector<uint8_t> out;
  for (size_t k = 0; k < sections.size(); ++k) {
    ASSERT_FALSE(sections[k].empty());
    int refused = 0;
    for (size_t byte = 0; byte < sections[k].size(); ++byte)
      for (int bit = 0; bit < 8; ++bit) {
        std::vector<std::vector<uint8_t>> damaged = sections;
        damaged[k][byte] ^= static_cast<uint8_t>(1 << bit);
        const Status st = decode(damaged, out);
        if (!st.ok()) {
          EXPECT_EQ(st.code(), StatusCode::kCorrupt);
          EXPECT_NE(st.message().find("chunk " + std::to_string(k)), std::string::npos) << st.message();
          ++refused;
          continue;
        }
        check(k, out);
      }
    EXPECT_GT(refused, 0);
    for (size_t len = 0; len < sections[k].size(); ++len) {
      std::vector<std::vector<uint8_t>> cut = sections;
      cut[k].resize(len);
      const Status st = decode(cut, out);
      if (len == 0 && empty_decodes) {
        EXPECT_TRUE(st.ok());
      } else {
        EXPECT_EQ(st.code(), StatusCode::kCorrupt) << k << " " << len;
      }
    }
  }
}

// The same for a bricked layer's sections, a chunk each (15.0): below the
// chunks' checksums, a damaged or cut section is refused, naming its
// chunk, or gives regions in the table; a section where a chunk owns no
// kept cell, or none where it does, is refused.
TEST(Regions, DamagedChunkSectionsGiveRegionsInTheTableOrAnError) {
  const std::vector<GridPoint> g = test::random_grid_points(400, 8, 2);
  const TetMesh dt = delaunay_tetrahedralize(g).value();
  std::vector<uint32_t> rank(g.size());
  for (uint32_t v = 0; v < rank.size(); ++v) rank[v] = v;
  std::vector<uint32_t> chunk_of_cell(dt.cells.size());
  std::vector<uint8_t> region(dt.cells.size());
  std::mt19937 rng(4);
  for (size_t c = 0; c < region.size(); ++c) {
    chunk_of_cell[c] = g[dt.cells[c][0]].y < 100 ? 0 : g[dt.cells[c][0]].y < 180 ? 1 : 2;
    region[c] = g[dt.cells[c][0]].z < 60 ? 0 : (g[dt.cells[c][0]].x < 128) ? 1 : 2 + rng() % 3;
  }
  const ChunkCells chunks = chunk_cells(dt, chunk_of_cell, 3, rank);
  const std::vector<std::vector<uint8_t>> sections =
      encode_region_chunks(dt, chunks, chunk_of_cell, region, 4);
  ASSERT_EQ(sections.size(), 3u);
  const auto decode = [&](const std::vector<std::vector<uint8_t>>& bytes, size_t count,
                          std::vector<uint8_t>& out) {
    std::vector<std::span<const uint8_t>> spans(bytes.begin(), bytes.end());
    out.assign(region.size(), 0);
    for (size_t c = 0; c < region.size(); ++c) out[c] = region[c] != 0;
    return decode_region_chunks(spans, dt, chunks, chunk_of_cell, count, out);
  };
  std::vector<uint8_t> out;
  ASSERT_TRUE(decode(sections, 4, out).ok());
  EXPECT_EQ(out, region);
  // Each chunk alone: its cells' regions do not depend on the others.
  expect_chunk_damage_refused_or_checked(
      sections, [&](const auto& bytes, std::vector<uint8_t>& got) { return decode(bytes, 4, got); },
      [&](size_t k, const std::vector<uint8_t>& got) {
        for (size_t c = 0; c < got.size(); ++c) {
          EXPECT_EQ(got[c] != 0, region[c] != 0);
          EXPECT_LE(got[c], 4);
          if (chunk_of_cell[c] != k) {
            EXPECT_EQ(got[c], region[c]);
          }
        }
      },
      false);
  // A section of one region's stream, or for a chunk with nothing kept.
  EXPECT_EQ(decode(sections, 1, out).code(), StatusCode::kCorrupt);
  std::vector<uint8_t> none = region;
  for (size_t c = 0; c < none.size(); ++c)
    if (chunk_of_cell[c] == 1) none[c] = 0;
  std::vector<std::span<const uint8_t>> spans(sections.begin(), sections.end());
  std::vector<uint8_t> kept(none.size());
  for (size_t c = 0; c < none.size(); ++c) kept[c] = none[c] != 0;
  EXPECT_EQ(decode_region_chunks(spans, dt, chunks, chunk_of_cell, 4, kept).code(), StatusCode::kCorrupt);
  // A kept cell whose brick has no chunk.
  std::vector<uint32_t> orphan = chunk_of_cell;
  for (size_t c = 0; c < orphan.size(); ++c)
    if (region[c]) {
      orphan[c] = kNoCarvingChunk;
      break;
    }
  for (size_t c = 0; c < region.size(); ++c) kept[c] = region[c] != 0;
  EXPECT_EQ(decode_region_chunks(spans, dt, chunk_cells(dt, orphan, 3, rank), orphan, 4, kept).code(),
            StatusCode::kCorrupt);
}

// Every prefix of a bricked stream decodes to whole levels or ends as
// truncated, `check` holding of each prefix's finest level as meshdec
// writes it; a bit flipped after the header (300 at random) is caught.
void expect_cut_or_damaged_ends_cleanly(const std::vector<uint8_t>& bytes,
                                        const std::function<void(const OutputMesh&)>& check) {
  for (size_t len = 0; len < bytes.size(); len += (len < 300 ? 3 : 53)) {
    ProgressiveDecoder d;
    const Status fed = d.feed(std::span(bytes).first(len));
    ASSERT_TRUE(fed.ok()) << len << ": " << fed.message();
    EXPECT_EQ(d.finish().code(), StatusCode::kTruncated) << len;
    if (d.finest_level() >= 0) check(decoded_mesh(d, "prefix"));
  }
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<uint8_t> damaged = bytes;
    const size_t byte = kHeaderSize + rng() % (damaged.size() - kHeaderSize);
    damaged[byte] ^= static_cast<uint8_t>(1 << (rng() % 8));
    ProgressiveDecoder d;
    const Status s = d.feed(damaged);
    if (s.ok() && d.finish().ok()) {
      (void)d.level_cells();
      EXPECT_FALSE(d.mesh_status().ok()) << "byte " << byte;
    }
  }
}

// A bricked stream with regions: every prefix decodes to whole levels or
// ends as truncated, their cells each with a region; a bit flipped in a
// chunk is caught by its checksum.
TEST(Regions, BrickedStreamsEndCleanlyWhenCutOrDamaged) {
  const RegionInput in = three_materials(700, 9);
  EncodeOptions options = small_bricks(400);
  const Encoded e = encode_regions(in, {{3, "a"}, {7, "b"}}, options);
  ASSERT_FALSE(e.bytes.empty());
  expect_cut_or_damaged_ends_cleanly(e.bytes,
                                     [](const OutputMesh& m) { EXPECT_EQ(m.region.size(), m.cells.size()); });
}

TEST(Regions, TableRoundTripsAndRefusesWhatIsNotATable) {
  const std::vector<RegionLabel> table = {{-5, ""}, {1, "aluminium"}, {70000, std::string(64, 'x')}};
  ASSERT_TRUE(check_region_table(table).ok());
  const std::vector<uint8_t> bytes = write_region_table(table);
  std::vector<RegionLabel> back;
  size_t consumed = 0;
  ASSERT_TRUE(parse_region_table(bytes, back, consumed).ok());
  EXPECT_EQ(consumed, bytes.size());
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].label, -5);
  EXPECT_EQ(back[2].name, std::string(64, 'x'));
  for (size_t len = 0; len < bytes.size(); ++len)
    EXPECT_EQ(parse_region_table(std::span(bytes).first(len), back, consumed).code(),
              StatusCode::kNeedMoreInput);
  EXPECT_FALSE(check_region_table(std::vector<RegionLabel>{{1, ""}, {1, ""}}).ok());
  EXPECT_FALSE(check_region_table(std::vector<RegionLabel>{{1, std::string(65, 'y')}}).ok());
  EXPECT_FALSE(check_region_table(std::vector<RegionLabel>{}).ok());
}

// The readers take the labels their formats carry; the writers give them
// back where the format holds them.
TEST(Regions, ReadersAndWritersCarryTheLabels) {
  const auto dir = std::filesystem::temp_directory_path() / ("dtm_regions_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  OutputMesh m;
  m.grid.step = 0.5;
  m.grid.qbits = 6;
  m.points = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {4, 4, 4}};
  m.cells = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  if (orientation({4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {4, 4, 4}) < 0) std::swap(m.cells[1][0], m.cells[1][1]);
  m.region = {5, -3};
  m.region_names = {{5, "core"}};
  for (const char* ext : {".msh", ".mesh", ".node"}) {
    const std::string path = (dir / (std::string("two") + ext)).string();
    for (const auto& [file, text] : render_mesh(m, format_for_path(path), path, {})) {
      std::ofstream(file, std::ios::binary) << text;
    }
    const InputMesh back = read_input(path);
    ASSERT_EQ(back.tets.size(), 2u) << ext;
    // gmsh's file holds a block of elements a region: the order changes.
    std::vector<int32_t> labels = back.tet_regions;
    if (std::string(ext) == ".msh") std::sort(labels.begin(), labels.end(), std::greater<>());
    EXPECT_EQ(labels, (std::vector<int32_t>{5, -3})) << ext;
    if (std::string(ext) == ".msh") {
      EXPECT_EQ(back.region_names.at(5), "core");
    }
  }
  const std::string vtu = (dir / "two.vtu").string();
  const std::string text = render_mesh(m, MeshFormat::kVtu, vtu, {}).front().second;
  EXPECT_NE(text.find("<CellData Scalars=\"region\">"), std::string::npos);
  std::ofstream(vtu, std::ios::binary) << text;
  InputMesh back = read_input(vtu);
  choose_regions(back, "", vtu);
  EXPECT_EQ(back.tet_regions, (std::vector<int32_t>{5, -3}));
  EXPECT_EQ(back.region_source, "cell array 'region'");
  back = read_input(vtu);
  EXPECT_THROW(choose_regions(back, "material", vtu), FormatError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dtm

namespace dtm {
namespace {

using Tri = std::array<uint32_t, 3>;
using Vec = std::array<double, 3>;

Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Squared distance from p to the triangle (a, b, c) (Ericson's closest point).
double squared_distance(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const auto at = [&](double u, double v) {  // a + u ab + v ac
    const Vec q = {a[0] + u * ab[0] + v * ac[0], a[1] + u * ab[1] + v * ac[1], a[2] + u * ab[2] + v * ac[2]};
    const Vec d = sub(p, q);
    return dot(d, d);
  };
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return at(0, 0);
  const Vec bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return at(1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(d1 / (d1 - d3), 0);
  const Vec cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return at(0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(0, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at(1 - w, w);
  }
  const double denom = 1 / (va + vb + vc);
  return at(vb * denom, vc * denom);
}

// The three materials' outer boundary, tagged on two sides (11 where x <
// 300, 12 where z > 800), and the ball's interface tagged 13.
struct TaggedFaces {
  std::vector<Tri> faces;
  std::vector<int32_t> tags;
};
TaggedFaces tag_sides(const RegionInput& in) {
  TaggedFaces t;
  std::map<Tri, std::vector<size_t>> sides;  // sorted face -> the tetrahedra that have it
  for (size_t c = 0; c < in.tets.size(); ++c)
    for (int skip = 0; skip < 4; ++skip) {
      Tri f;
      int k = 0;
      for (int i = 0; i < 4; ++i)
        if (i != skip) f[static_cast<size_t>(k++)] = in.tets[c][static_cast<size_t>(i)];
      std::sort(f.begin(), f.end());
      sides[f].push_back(c);
    }
  for (const auto& [f, cells] : sides) {
    Vec centroid{0, 0, 0};
    for (uint32_t v : f)
      centroid = {centroid[0] + in.points[v].x / 3, centroid[1] + in.points[v].y / 3,
                  centroid[2] + in.points[v].z / 3};
    int32_t tag = 0;
    if (cells.size() == 1 && centroid[0] < 300) tag = 11;
    if (cells.size() == 1 && centroid[2] > 800) tag = 12;
    if (cells.size() == 2 && (in.labels[cells[0]] == 7) != (in.labels[cells[1]] == 7)) tag = 13;
    if (tag) t.faces.push_back(f), t.tags.push_back(tag);
  }
  return t;
}

// The input's tagged triangles: on the grid (sorted corners) with their
// tags, and in the input's units for distances.
struct TagPatches {
  std::map<std::array<GridPoint, 3>, int32_t> tag_of;
  std::vector<std::pair<std::array<Vec, 3>, int32_t>> surface;
};
TagPatches tag_patches(const RegionInput& in, const TaggedFaces& tagged) {
  const QuantizedPoints q = quantize(in.points, 14).value();
  TagPatches p;
  for (size_t i = 0; i < tagged.faces.size(); ++i) {
    std::array<GridPoint, 3> k;
    std::array<Vec, 3> corners;
    for (size_t j = 0; j < 3; ++j) {
      k[j] = q.points[q.input_to_point[tagged.faces[i][j]]];
      const InputPoint pt = in.points[tagged.faces[i][j]];
      corners[j] = {pt.x, pt.y, pt.z};
    }
    std::sort(k.begin(), k.end());
    p.tag_of[k] = tagged.tags[i];
    p.surface.push_back({corners, tagged.tags[i]});
  }
  return p;
}

// Every level of `bytes` decoded: a tagged input triangle that is a face
// keeps its own tag, any other tagged face lies within `reach` of a
// triangle of its tag's patch, every level has all three tags, and level 0
// has `tagged` tagged triangles among its faces (and, `only`, no other
// tagged face).
void expect_tags_on_patches(const std::vector<uint8_t>& bytes, const TagPatches& patches, double reach,
                            size_t tagged, bool only, size_t level_count) {
  ProgressiveDecoder decoder;
  size_t levels = 0;
  ASSERT_TRUE(decoder
                  .feed(bytes,
                        [&](const ProgressiveDecoder& d, const DecodedLevel& level) {
                          ++levels;
                          const OutputMesh m = decoded_mesh(d, "faces");
                          ASSERT_EQ(m.faces.size(), m.face_tags.size());
                          std::map<int32_t, size_t> count;
                          size_t own = 0;  // tagged triangles among the faces
                          for (size_t f = 0; f < m.faces.size(); ++f) {
                            ++count[m.face_tags[f]];
                            std::array<GridPoint, 3> k = {m.points[m.faces[f][0]], m.points[m.faces[f][1]],
                                                          m.points[m.faces[f][2]]};
                            std::sort(k.begin(), k.end());
                            if (const auto it = patches.tag_of.find(k); it != patches.tag_of.end()) {
                              EXPECT_EQ(m.face_tags[f], it->second) << "level " << level.level;
                              ++own;
                              continue;
                            }
                            Vec c{0, 0, 0};
                            for (const GridPoint& g : k) {
                              const InputPoint p = m.grid.to_input(g);
                              c = {c[0] + p.x / 3, c[1] + p.y / 3, c[2] + p.z / 3};
                            }
                            double best = INFINITY;
                            for (const auto& [t, tag] : patches.surface)
                              if (tag == m.face_tags[f])
                                best = std::min(best, squared_distance(c, t[0], t[1], t[2]));
                            EXPECT_LE(std::sqrt(best), reach)
                                << "level " << level.level << " tag " << m.face_tags[f];
                          }
                          EXPECT_EQ(count.size(), 3u) << "level " << level.level;
                          if (level.level == 0) {
                            EXPECT_EQ(own, tagged);
                            if (only) {
                              EXPECT_EQ(m.faces.size(), tagged);
                            }
                          }
                        })
                  .ok());
  EXPECT_TRUE(decoder.finish().ok());
  EXPECT_EQ(levels, level_count);
}

EncodeInput tagged_input(const RegionInput& in, const TaggedFaces& tagged) {
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.tetrahedron_regions = in.labels;
  input.tagged_faces = tagged.faces;
  input.face_tags = tagged.tags;
  input.face_tag_names = {{11, "west"}, {13, "ball"}};
  return input;
}

TEST(Faces, EveryLevelsSurfaceCarriesTheTagsOfItsPatches) {
  const RegionInput in = three_materials(2500, 11);
  const TaggedFaces tagged = tag_sides(in);
  ASSERT_GT(tagged.faces.size(), 100u);
  EncodeOptions options;
  options.dmax = 8;
  const auto encoded = encode(tagged_input(in, tagged), options);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  const EncodeReport& r = encoded->report;
  ASSERT_EQ(r.face_tags.size(), 3u);
  EXPECT_EQ(r.face_tags[0].name, "west");
  // The input is Delaunay: level 0 has every tagged triangle as a face.
  EXPECT_EQ(r.tagged_faces, tagged.faces.size());
  EXPECT_EQ(r.tagged_faces_kept, tagged.faces.size());
  ASSERT_GE(r.levels.size(), 3u);
  const double reach = 8 * (1 + 1e-6) + 2 * r.grid.step;
  expect_tags_on_patches(encoded->bytes, tag_patches(in, tagged), reach, tagged.faces.size(), true,
                         r.levels.size());
}

// A level's tagged faces as (corners, the outward one first turned to
// start at the least; tag), from a whole decoder or a region reader.
using OrientedFace = std::array<GridPoint, 3>;
OrientedFace oriented(std::array<GridPoint, 3> f) {
  std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return f;
}
std::map<OrientedFace, int32_t> faces_of(const OutputMesh& m) {
  std::map<OrientedFace, int32_t> out;
  for (size_t f = 0; f < m.faces.size(); ++f)
    out[oriented({m.points[m.faces[f][0]], m.points[m.faces[f][1]], m.points[m.faces[f][2]]})] =
        m.face_tags[f];
  return out;
}

// Bricked streams (17.0): each chunk codes the tags of its brick's kept
// cells' faces. Every level's tagged faces lie on their patches (level 0
// keeps those of its faces); pieces hold the whole level's tagged faces, each once, turned the same way, and
// a box those of its cells; one process and 2 or 3 ranks write the same bytes.
TEST(Faces, BrickedLevelsTagTheirSurfaceInEveryChunk) {
  const RegionInput in = three_materials(2500, 11);
  const TaggedFaces tagged = tag_sides(in);
  EncodeOptions options = small_bricks(600);
  options.dmax = 8;
  const auto encoded = encode(tagged_input(in, tagged), options);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  const std::vector<uint8_t>& bytes = encoded->bytes;
  const EncodeReport& r = encoded->report;
  EXPECT_EQ(bytes[8], kVersionMajorBrickedFaces);
  StreamHeader h;
  ASSERT_TRUE(parse_header(bytes, h).ok());
  EXPECT_TRUE((h.flags & kFlagBricks) && (h.flags & kFlagFaces));
  h.version_major = kVersionMajorBrickedFaces - 1;  // bricked faces before 17.0: refused
  EXPECT_EQ(parse_header(write_header(h), h).code(), StatusCode::kCorrupt);
  // (Level 0 keeps no cell above its kept radius: a few large cells on the
  // convex hull of these random points are not in it, and their tagged
  // sides with them.)
  EXPECT_GT(r.tagged_faces_kept, tagged.faces.size() * 9 / 10);
  ASSERT_GE(r.levels.size(), 3u);
  ASSERT_EQ(r.face_bytes.size(), r.levels.size());
  for (uint64_t b : r.face_bytes) EXPECT_GT(b, 0u);
  const double reach = 8 * (1 + 1e-6) + 2 * r.grid.step;
  expect_tags_on_patches(bytes, tag_patches(in, tagged), reach, r.tagged_faces_kept, false, r.levels.size());

  MemorySource source(bytes);
  for (int level = 0; level < 2; ++level) {
    SCOPED_TRACE("level " + std::to_string(level));
    DecoderOptions stop;
    stop.stop_after_level = level;
    ProgressiveDecoder whole(stop);
    ASSERT_TRUE(whole.feed(bytes).ok());
    const OutputMesh all = decoded_mesh(whole, "whole");
    const std::map<OrientedFace, int32_t> want = faces_of(all);
    ASSERT_GT(want.size(), 50u);
    std::map<OrientedFace, int32_t> pieces;
    size_t in_pieces = 0;
    for (int piece = 0; piece < 3; ++piece) {
      const auto got = decode_piece(source, level, piece, 3);
      ASSERT_TRUE(got.ok()) << got.status().message();
      ASSERT_EQ(got->face_tags.size(), 3u);
      const OutputMesh m = region_output(*got, all.grid);
      in_pieces += m.faces.size();
      const std::map<OrientedFace, int32_t> here = faces_of(m);
      pieces.insert(here.begin(), here.end());
    }
    EXPECT_EQ(in_pieces, want.size());
    EXPECT_TRUE(pieces == want);
    // A box (the lower half in x): the tagged faces of the cells that meet it.
    GridBox box;
    box.lo = {0, 0, 0};
    box.hi = {int64_t{1} << 13, (int64_t{1} << 14) - 1, (int64_t{1} << 14) - 1};
    std::set<OrientedFace> of_box_cells;
    for (const auto& cell : all.cells) {
      if (!cell_meets(all.points, cell, box)) continue;
      for (int skip = 0; skip < 4; ++skip) {
        std::array<GridPoint, 3> f{};
        for (int i = 0, j = 0; i < 4; ++i)
          if (i != skip) f[static_cast<size_t>(j++)] = all.points[cell[static_cast<size_t>(i)]];
        // Turned out of the cell (the cell behind it).
        if (dtm::orientation(f[0], f[1], f[2], all.points[cell[static_cast<size_t>(skip)]]) > 0)
          std::swap(f[1], f[2]);
        of_box_cells.insert(oriented(f));
      }
    }
    std::map<OrientedFace, int32_t> want_box;
    for (const auto& [f, tag] : want)
      if (of_box_cells.contains(f)) want_box[f] = tag;
    const auto got = decode_region(source, box, level);
    ASSERT_TRUE(got.ok()) << got.status().message();
    EXPECT_TRUE(faces_of(region_output(*got, all.grid)) == want_box);
    EXPECT_GT(want_box.size(), 10u);
    EXPECT_LT(want_box.size(), want.size());
  }

  // Every rank given every tetrahedron and triangle: the same bytes.
  for (int ranks : {2, 3}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const auto made = test::on_ranks(ranks, true, [&](RankExchange& rank, int) {
      EncodeOptions on_rank = options;
      on_rank.exchange = &rank;
      const auto e = encode(tagged_input(in, tagged), on_rank);
      return e.ok() ? e->bytes : std::vector<uint8_t>{};
    });
    for (const auto& b : made) EXPECT_TRUE(b == bytes);
  }
}

// The tags change no level: the gmsh part of two materials
// (data/two_materials.msh) in blocks far smaller than it, with and without
// its tagged faces, has the same points and cells on every level (the
// faces' tags look farther than the blocks' analysis: in a pass of their
// own).
TEST(Faces, BrickedLevelsAreTheSameWithoutTheTags) {
  const InputMesh part = read_input(test::data_path("two_materials.msh"));
  ASSERT_FALSE(part.tagged_faces.empty());
  EncodeInput input;
  input.points = part.points;
  input.tetrahedra = part.tets;
  input.tetrahedron_regions = part.tet_regions;
  input.tagged_faces = part.tagged_faces;
  input.face_tags = part.face_tags;
  EncodeOptions options = small_bricks(400);
  options.dmax = 0.2;
  options.average_quality_floor = 0;
  const auto with = encode(input, options);
  ASSERT_TRUE(with.ok()) << with.status().message();
  EXPECT_EQ(with->report.tagged_faces_kept, with->report.tagged_faces);
  EncodeInput untagged = input;
  untagged.tagged_faces = {};
  untagged.face_tags = {};
  const auto without = encode(untagged, options);
  ASSERT_TRUE(without.ok()) << without.status().message();
  ASSERT_EQ(without->report.levels.size(), with->report.levels.size());
  ASSERT_GE(with->report.levels.size(), 3u);
  for (int level = 0; level < static_cast<int>(with->report.levels.size()); ++level) {
    DecoderOptions stop;
    stop.stop_after_level = level;
    ProgressiveDecoder a(stop), b(stop);
    ASSERT_TRUE(a.feed(with->bytes).ok() && b.feed(without->bytes).ok());
    EXPECT_TRUE(a.points() == b.points()) << level;
    // (The same cells; their order follows the chunks, which a brick's
    // face section alone may add.)
    std::vector<std::array<uint32_t, 4>> ca = a.carved_cells(), cb = b.carved_cells();
    for (auto* cells : {&ca, &cb}) {
      for (auto& c : *cells) std::sort(c.begin(), c.end());
      std::sort(cells->begin(), cells->end());
    }
    EXPECT_TRUE(ca == cb) << level;
  }
}

// On ranks, tagged faces need every tetrahedron and the same tagged
// triangles on every rank: a rank given half the tetrahedra, other
// triangles, none, a tag of its own or a triangle naming no point makes
// every rank refuse, none waiting for the others.
TEST(Faces, RanksGivenOtherFacesRefuseTogether) {
  const RegionInput in = three_materials(600, 4);
  const TaggedFaces tagged = tag_sides(in);
  EncodeOptions options = small_bricks(300);
  options.dmax = 8;
  const EncodeInput input = tagged_input(in, tagged);
  ASSERT_TRUE(encode(input, options).ok());
  const std::vector<Tet> half(in.tets.begin(),
                              in.tets.begin() + static_cast<std::ptrdiff_t>(in.tets.size() / 2));
  const std::vector<int32_t> half_labels(in.labels.begin(),
                                         in.labels.begin() + static_cast<std::ptrdiff_t>(half.size()));
  const std::vector<Tri> fewer(tagged.faces.begin() + 1, tagged.faces.end());
  const std::vector<int32_t> fewer_tags(tagged.tags.begin() + 1, tagged.tags.end());
  std::vector<int32_t> own_tag = tagged.tags;
  own_tag[0] = 99;
  std::vector<Tri> beyond = tagged.faces;
  beyond[0][0] = static_cast<uint32_t>(in.points.size());
  // (Rank 1's input made by `given`.)
  const auto codes = [&](const std::function<void(EncodeInput&)>& given) {
    return test::on_ranks(2, true, [&](RankExchange& rank, int r) {
      EncodeOptions on_rank = options;
      on_rank.exchange = &rank;
      EncodeInput mine = input;
      if (r == 1) given(mine);
      return encode(mine, on_rank).status().code();
    });
  };
  const std::vector<StatusCode> refused(2, StatusCode::kInvalidInput);
  EXPECT_EQ(codes([&](EncodeInput& i) { i.tetrahedra = half, i.tetrahedron_regions = half_labels; }),
            refused);
  EXPECT_EQ(codes([&](EncodeInput& i) { i.tagged_faces = fewer, i.face_tags = fewer_tags; }), refused);
  EXPECT_EQ(codes([&](EncodeInput& i) { i.tagged_faces = {}, i.face_tags = {}; }), refused);
  EXPECT_EQ(codes([&](EncodeInput& i) { i.face_tags = own_tag; }), refused);
  EXPECT_EQ(codes([&](EncodeInput& i) { i.tagged_faces = beyond; }), refused);
  // A name of a label or tag nothing has (it would be lost), given to one rank.
  EXPECT_EQ(codes([&](EncodeInput& i) { i.region_names = {{8, "nothing"}}; }), refused);
  EXPECT_EQ(codes([&](EncodeInput& i) { i.face_tag_names[99] = "nothing"; }), refused);
}

// Below the chunks' checksums: a damaged or cut face section of a chunk is
// refused, naming it, or gives tags in the table, the other chunks' as
// they were; a chunk codes the faces of its kept cells but those inside
// it (and an interface from its higher side).
TEST(Faces, DamagedChunkSectionsGiveTagsInTheTableOrAnError) {
  const std::vector<GridPoint> g = test::random_grid_points(500, 8, 6);
  const TetMesh dt = delaunay_tetrahedralize(g).value();
  std::vector<uint32_t> rank(g.size());
  for (uint32_t v = 0; v < rank.size(); ++v) rank[v] = v;
  std::vector<uint32_t> chunk_of_cell(dt.cells.size());
  std::vector<uint8_t> kept(dt.cells.size());
  for (size_t c = 0; c < kept.size(); ++c) {
    const GridPoint& p = g[dt.cells[c][0]];
    chunk_of_cell[c] = p.y < 100 ? 0 : p.y < 180 ? 1 : 2;
    kept[c] = p.z < 60 ? 0 : p.x < 128 ? 1 : 2;
  }
  const ChunkCells chunks = chunk_cells(dt, chunk_of_cell, 3, rank);
  const ChunkFaces faces = chunk_faces(dt, chunks, chunk_of_cell, kept, rank);
  ASSERT_EQ(faces.first.size(), 4u);
  // Which faces: each kept cell's, but for a kept cell of its chunk across
  // whose region is not above its own.
  size_t want = 0;
  for (size_t c = 0; c < kept.size(); ++c)
    for (int k = 0; kept[c] && k < 4; ++k) {
      const int32_t n = dt.neighbors[c][static_cast<size_t>(k)];
      want += !(n >= 0 && chunk_of_cell[static_cast<size_t>(n)] == chunk_of_cell[c] &&
                kept[static_cast<size_t>(n)] != 0 && kept[static_cast<size_t>(n)] <= kept[c]);
    }
  EXPECT_EQ(faces.faces.size(), want);
  std::vector<uint8_t> label(faces.faces.size());
  for (size_t f = 0; f < label.size(); ++f) {
    const GridPoint& p = g[dt.cells[faces.faces[f].cell][0]];
    label[f] = p.x < 100 ? 2 : p.z > 200 ? 3 : 1;
  }
  const std::vector<std::vector<uint8_t>> sections = encode_face_chunks(faces, label, 2);
  ASSERT_EQ(sections.size(), 3u);
  const auto decode = [&](const std::vector<std::vector<uint8_t>>& bytes, std::vector<uint8_t>& out) {
    std::vector<std::span<const uint8_t>> spans(bytes.begin(), bytes.end());
    return decode_face_chunks(spans, faces, 2, out);
  };
  std::vector<uint8_t> out;
  ASSERT_TRUE(decode(sections, out).ok());
  EXPECT_EQ(out, label);
  // (Cut to nothing, a chunk's faces have no tag: a whole decoder then
  // finds them no different; cut inside, refused.)
  expect_chunk_damage_refused_or_checked(
      sections, decode,
      [&](size_t k, const std::vector<uint8_t>& got) {
        for (size_t f = 0; f < got.size(); ++f) {
          EXPECT_TRUE(got[f] >= 1 && got[f] <= 3);
          if (f < faces.first[k] || f >= faces.first[k + 1]) {
            EXPECT_EQ(got[f], label[f]);
          }
        }
      },
      true);
  // No tag anywhere: no section.
  for (const auto& s : encode_face_chunks(faces, std::vector<uint8_t>(faces.faces.size(), 1), 2))
    EXPECT_TRUE(s.empty());
}

// A bricked stream with tagged faces: every prefix decodes to whole levels
// or ends as truncated, their faces each with a tag of the table; a bit
// flipped in the stream is caught.
TEST(Faces, BrickedStreamsEndCleanlyWhenCutOrDamaged) {
  const RegionInput in = three_materials(700, 9);
  const TaggedFaces tagged = tag_sides(in);
  EncodeOptions options = small_bricks(400);
  options.dmax = 8;
  const auto e = encode(tagged_input(in, tagged), options);
  ASSERT_TRUE(e.ok()) << e.status().message();
  expect_cut_or_damaged_ends_cleanly(e->bytes, [](const OutputMesh& m) {
    EXPECT_EQ(m.face_tags.size(), m.faces.size());
    EXPECT_FALSE(m.faces.empty());
  });
}

// meshdec --box of a stream that is not bricked: the level decoded whole,
// the box cut from it with what it carries. Every cell of the whole level
// meeting the box is there with its region and cell data, every tagged face
// of those cells with its tag, each vertex with its number in the whole
// level and its `boundary`; nothing else.
TEST(Faces, ABoxOfAWholeStreamKeepsTheTagsCellDataAndBoundary) {
  const RegionInput in = three_materials(1500, 5);
  const TaggedFaces tagged = tag_sides(in);
  std::vector<double> load(in.tets.size());
  for (size_t t = 0; t < load.size(); ++t) load[t] = static_cast<double>(t % 97) + 0.25;
  const std::vector<EncodeInput::Field> cell_fields = {{"load", ValueType::kF64, 1, load}};
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.tetrahedron_regions = in.labels;
  input.tagged_faces = tagged.faces;
  input.face_tags = tagged.tags;
  input.cell_fields = cell_fields;
  EncodeOptions options;
  options.dmax = 8;
  const auto encoded = encode(input, options);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  const std::string dir = ::testing::TempDir() + "/whole_box";
  std::filesystem::create_directories(dir);
  const std::string stream = dir + "/s.dtm", box = dir + "/box.vtu";
  std::ofstream(stream, std::ios::binary)
      .write(reinterpret_cast<const char*>(encoded->bytes.data()),
             static_cast<std::streamsize>(encoded->bytes.size()));
  // The lower half in x, in the input's units.
  const auto r = test::run_command(std::string(DTM_MESHDEC) + " " + stream + " -o " + box +
                                   " --box -1 -1 -1 500 2000 2000");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("not a bricked stream: decoded whole"), std::string::npos) << r.output;

  ProgressiveDecoder decoder;
  ASSERT_TRUE(decoder.feed(encoded->bytes).ok());
  ASSERT_TRUE(decoder.finish().ok());
  const OutputMesh whole = decoded_mesh(decoder, "whole");
  ASSERT_FALSE(whole.faces.empty());
  ASSERT_EQ(whole.cell_fields.size(), 1u);
  using Key3 = std::array<std::array<double, 3>, 3>;
  using Key4 = std::array<std::array<double, 3>, 4>;
  const auto at = [](const Grid& g, const GridPoint& p) {
    const InputPoint q = g.to_input(p);
    return std::array<double, 3>{q.x, q.y, q.z};
  };
  std::map<Key4, std::pair<int32_t, uint64_t>> want_cells;  // region, load bits
  // The box's cells' faces turned out of them, from their least corner: a
  // tagged face goes with the cell the surface takes it from.
  const auto from_least = [](std::array<uint32_t, 3> f) {
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    return f;
  };
  std::set<std::array<uint32_t, 3>> sides;
  for (size_t c = 0; c < whole.cells.size(); ++c) {
    Key4 k;
    bool meets = false;
    for (size_t i = 0; i < 4; ++i) {
      k[i] = at(whole.grid, whole.points[whole.cells[c][i]]);
      meets = meets || k[i][0] <= 500;
    }
    if (!meets) continue;
    std::sort(k.begin(), k.end());
    want_cells[k] = {whole.region[c], whole.cell_fields[0].bits[c]};
    const auto& t = whole.cells[c];
    for (int skip = 0; skip < 4; ++skip) {
      std::array<uint32_t, 3> f{};
      for (int i = 0, j = 0; i < 4; ++i)
        if (i != skip) f[static_cast<size_t>(j++)] = t[static_cast<size_t>(i)];
      if (dtm::orientation(whole.points[f[0]], whole.points[f[1]], whole.points[f[2]],
                           whole.points[t[static_cast<size_t>(skip)]]) > 0)
        std::swap(f[1], f[2]);
      sides.insert(from_least(f));
    }
  }
  std::map<Key3, int32_t> want_faces;
  size_t across = 0;  // tagged faces of the box's cells that go with a cell outside it
  for (size_t f = 0; f < whole.faces.size(); ++f) {
    if (!sides.contains(from_least(whole.faces[f]))) {
      std::array<uint32_t, 3> reversed = whole.faces[f];
      std::swap(reversed[1], reversed[2]);
      across += sides.contains(from_least(reversed));
      continue;
    }
    Key3 k;
    for (size_t i = 0; i < 3; ++i) k[i] = at(whole.grid, whole.points[whole.faces[f][i]]);
    std::sort(k.begin(), k.end());
    want_faces[k] = whole.face_tags[f];
  }
  ASSERT_GT(want_faces.size(), 10u);
  EXPECT_GT(across, 0u);  // (the ball's interface crosses the cut: some go with cells outside)
  ASSERT_LT(want_cells.size(), whole.cells.size());

  InputMesh got = read_input(box);
  choose_regions(got, "", box);  // the integer cell array "region", as meshenc takes it
  const auto point = [&](uint32_t v) {
    return std::array<double, 3>{got.points[v].x, got.points[v].y, got.points[v].z};
  };
  ASSERT_EQ(got.tets.size(), want_cells.size());
  ASSERT_EQ(got.tet_regions.size(), got.tets.size());
  ASSERT_EQ(got.cell_fields.size(), 1u);
  for (size_t c = 0; c < got.tets.size(); ++c) {
    Key4 k;
    for (size_t i = 0; i < 4; ++i) k[i] = point(got.tets[c][i]);
    std::sort(k.begin(), k.end());
    const auto it = want_cells.find(k);
    ASSERT_NE(it, want_cells.end()) << c;
    EXPECT_EQ(got.tet_regions[c], it->second.first) << c;
    EXPECT_EQ(bits_of(got.cell_fields[0].values[c], ValueType::kF64), it->second.second) << c;
  }
  ASSERT_EQ(got.tagged_faces.size(), want_faces.size());
  for (size_t f = 0; f < got.tagged_faces.size(); ++f) {
    Key3 k;
    for (size_t i = 0; i < 3; ++i) k[i] = point(got.tagged_faces[f][i]);
    std::sort(k.begin(), k.end());
    const auto it = want_faces.find(k);
    ASSERT_NE(it, want_faces.end()) << f;
    EXPECT_EQ(got.face_tags[f], it->second) << f;
  }
  // vertex_id names each vertex in the whole level; boundary is the level's.
  const VertexField* ids = nullptr;
  const VertexField* boundary = nullptr;
  for (const VertexField& f : got.fields) {
    if (f.name == "vertex_id") ids = &f;
    if (f.name == "boundary") boundary = &f;
  }
  ASSERT_TRUE(ids && boundary);
  for (size_t v = 0; v < got.points.size(); ++v) {
    const auto w = static_cast<uint32_t>(ids->values[v]);
    ASSERT_LT(w, whole.points.size());
    EXPECT_EQ(point(static_cast<uint32_t>(v)), at(whole.grid, whole.points[w])) << v;
    EXPECT_EQ(boundary->values[v], whole.boundary[w]) << v;
  }
}

TEST(Faces, DamagedSectionsGiveTagsInTheTableOrAnError) {
  const std::vector<GridPoint> g = test::random_grid_points(500, 8, 6);
  const TetMesh dt = delaunay_tetrahedralize(g).value();
  std::vector<uint8_t> kept(dt.cells.size());
  for (size_t c = 0; c < kept.size(); ++c) kept[c] = g[dt.cells[c][0]].z < 160 ? 1 : 0;
  const SurfaceFaces surface = surface_faces(dt, kept);
  ASSERT_GT(surface.faces.size(), 50u);
  std::vector<uint8_t> tag(surface.faces.size());
  for (size_t f = 0; f < tag.size(); ++f) {
    const GridPoint& p = g[surface.faces[f].key[0]];
    tag[f] = p.x < 100 ? 2 : p.y < 100 ? 3 : 1;
  }
  const std::vector<uint8_t> section = encode_face_tags(surface, tag, 2);
  std::vector<uint8_t> back;
  ASSERT_TRUE(decode_face_tags(section, surface, 2, back).ok());
  EXPECT_EQ(back, tag);
  int refused = 0;
  for (size_t byte = 0; byte < section.size(); ++byte)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> damaged = section;
      damaged[byte] ^= static_cast<uint8_t>(1 << bit);
      const Status s = decode_face_tags(damaged, surface, 2, back);
      if (!s.ok()) {
        EXPECT_EQ(s.code(), StatusCode::kCorrupt);
        ++refused;
        continue;
      }
      for (uint8_t t : back) EXPECT_TRUE(t >= 1 && t <= 3);
    }
  EXPECT_GT(refused, 0);
  for (size_t len = 1; len < section.size(); ++len)
    EXPECT_EQ(decode_face_tags(std::span(section).first(len), surface, 2, back).code(), StatusCode::kCorrupt)
        << len;
  // No tag anywhere: no section.
  EXPECT_TRUE(encode_face_tags(surface, std::vector<uint8_t>(surface.faces.size(), 1), 2).empty());
}

TEST(Faces, ReadersAndWritersCarryTheTags) {
  const auto dir = std::filesystem::temp_directory_path() / ("dtm_faces_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  OutputMesh m;
  m.grid.step = 0.5;
  m.grid.qbits = 6;
  m.points = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}};
  m.cells = {{0, 1, 2, 3}};
  if (orientation({0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}) < 0) std::swap(m.cells[0][0], m.cells[0][1]);
  m.region = {5};
  m.faces = {{0, 2, 1}, {0, 1, 3}};
  m.face_tags = {21, 22};
  m.face_tag_names = {{21, "base"}};
  // (.vtk, ASCII and binary: the triangles after the tetrahedra, tagged by
  // CELL_DATA region, as the .vtu; .node: the .face's boundary markers.)
  for (const char* ext : {".msh", ".mesh", ".vtu", ".vtk", ".node"}) {
    const std::string path = (dir / (std::string("tagged") + ext)).string();
    for (const auto& [file, text] : render_mesh(m, format_for_path(path), path, {}))
      std::ofstream(file, std::ios::binary) << text;
    InputMesh back = read_input(path);
    choose_regions(back, "", path);
    ASSERT_EQ(back.tagged_faces.size(), 2u) << ext;
    std::vector<int32_t> tags = back.face_tags;
    std::sort(tags.begin(), tags.end());
    EXPECT_EQ(tags, (std::vector<int32_t>{21, 22})) << ext;
    EXPECT_EQ(back.tet_regions, (std::vector<int32_t>{5})) << ext;
    if (std::string(ext) == ".msh") {
      EXPECT_EQ(back.face_tag_names.at(21), "base");
    }
  }
  // The .node's .face: a mesh without tagged faces written over it replaces
  // it by one without faces (its markers would be read as this mesh's); a
  // tag 0, which a .face reads back as no tag, is said.
  const std::string node = (dir / "tagged.node").string();
  OutputMesh untagged = m;
  untagged.faces.clear();
  untagged.face_tags.clear();
  untagged.face_tag_names.clear();
  for (const auto& [file, text] : render_mesh(untagged, MeshFormat::kTetgen, node, {}))
    std::ofstream(file, std::ios::binary) << text;
  EXPECT_TRUE(read_input(node).tagged_faces.empty());
  OutputMesh zero = m;
  zero.face_tags = {0, 22};
  const auto said = not_written(zero, MeshFormat::kTetgen);
  EXPECT_TRUE(std::any_of(said.begin(), said.end(),
                          [](const std::string& s) { return s.find("the tag 0 of 1 faces") == 0; }));
  std::filesystem::remove_all(dir);
}

// Netgen's .vol: the regions are its materials 1..K (in the labels' order,
// named), every face of the surface a surface element (the 6 outer faces of
// two tetrahedra and their interface), each with its tag (0: none) and its
// domains, facing out of its domain; the tetrahedra turned as Netgen's.
TEST(Faces, NetgenVolHoldsEverySurfaceFaceWithItsDomains) {
  OutputMesh m;
  m.grid.step = 0.5;
  m.grid.qbits = 6;
  m.points = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {4, 4, 4}};
  m.cells = {{0, 1, 2, 3}, {1, 2, 3, 4}};
  const auto at = [&](uint32_t v) { return P4{m.points[v].x, m.points[v].y, m.points[v].z}; };
  for (auto& c : m.cells)
    if (orientation(at(c[0]), at(c[1]), at(c[2]), at(c[3])) < 0) std::swap(c[0], c[1]);
  m.region = {5, -3};
  m.region_names = {{5, "steel core"}};
  m.faces = {{0, 2, 1}, {1, 2, 3}};  // an outer face and the interface
  m.face_tags = {21, 30};
  m.face_tag_names = {{21, "base"}};
  const std::string path = ::testing::TempDir() + "/two.vol";
  for (const auto& [file, text] : render_mesh(m, format_for_path(path), path, {}))
    std::ofstream(file, std::ios::binary) << text;
  const InputMesh back = read_input(path);
  ASSERT_EQ(back.points.size(), 5u);
  ASSERT_EQ(back.tets.size(), 2u);
  for (size_t c = 0; c < 2; ++c) {
    auto a = back.tets[c], b = m.cells[c];
    EXPECT_LT(orientation(at(a[0]), at(a[1]), at(a[2]), at(a[3])), 0) << "Netgen's turn";
    std::sort(a.begin(), a.end()), std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b);
  }
  EXPECT_EQ(back.tet_regions, (std::vector<int32_t>{2, 1}));  // -3 is domain 1, 5 domain 2
  EXPECT_EQ(back.region_names, (std::map<int32_t, std::string>{{1, "region_-3"}, {2, "steel_core"}}));
  // A condition a kind of face (its tag and domains), named by its tag.
  ASSERT_EQ(back.tagged_faces.size(), 7u);
  std::map<std::array<uint32_t, 3>, int32_t> tags;
  for (size_t f = 0; f < 7; ++f) {
    const auto& t = back.tagged_faces[f];
    // Away from the cell it bounds (the interface: from domain 1's, cell 1).
    const auto corners = [&](const std::array<uint32_t, 4>& cell) {
      return std::count_if(cell.begin(), cell.end(),
                           [&](uint32_t v) { return v == t[0] || v == t[1] || v == t[2]; });
    };
    const size_t from = corners(m.cells[0]) == 3 && corners(m.cells[1]) != 3 ? 0 : 1;
    const auto& cell = m.cells[from];
    const uint32_t far = *std::find_if(cell.begin(), cell.end(),
                                       [&](uint32_t v) { return v != t[0] && v != t[1] && v != t[2]; });
    EXPECT_LT(orientation(at(t[0]), at(t[1]), at(t[2]), at(far)), 0) << f;
    auto key = t;
    std::sort(key.begin(), key.end());
    tags[key] = back.face_tags[f];
  }
  EXPECT_EQ(back.face_tag_names.at(tags.at({0, 1, 2})), "base");
  EXPECT_EQ(back.face_tag_names.at(tags.at({1, 2, 3})), "bc_30");
  for (const auto& [face, tag] : tags)
    if (face != std::array<uint32_t, 3>{0, 1, 2} && face != std::array<uint32_t, 3>{1, 2, 3}) {
      EXPECT_EQ(back.face_tag_names.at(tag), "default");
    }
  // In one region, the face between the tetrahedra is a surface element
  // only while it is tagged.
  m.region = {5, 5};
  for (const bool tagged : {true, false}) {
    if (!tagged) m.faces.pop_back(), m.face_tags.pop_back();
    for (const auto& [file, text] : render_mesh(m, format_for_path(path), path, {}))
      std::ofstream(file, std::ios::binary) << text;
    EXPECT_EQ(read_input(path).tagged_faces.size(), tagged ? 7u : 6u);
  }
  // Every face tagged 1 to K, one kind each (as a Netgen mesh's own
  // boundary conditions come back): the numbers are the tags, the names
  // theirs, whatever order the faces come in.
  m.region = {5, 5};
  m.faces = {{1, 2, 4}, {0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 4, 3}, {2, 3, 4}};
  m.face_tags = {3, 2, 5, 1, 6, 4};
  m.face_tag_names = {{1, "xmin"}, {3, "xmax"}};
  for (const auto& [file, text] : render_mesh(m, format_for_path(path), path, {}))
    std::ofstream(file, std::ios::binary) << text;
  const InputMesh numbered = read_input(path);
  ASSERT_EQ(numbered.tagged_faces.size(), 6u);
  for (size_t f = 0; f < 6; ++f) {
    auto t = numbered.tagged_faces[f];
    std::sort(t.begin(), t.end());
    const auto it = std::find_if(m.faces.begin(), m.faces.end(), [&](std::array<uint32_t, 3> g) {
      std::sort(g.begin(), g.end());
      return g == t;
    });
    ASSERT_NE(it, m.faces.end());
    EXPECT_EQ(numbered.face_tags[f], m.face_tags[static_cast<size_t>(it - m.faces.begin())]);
  }
  EXPECT_EQ(numbered.face_tag_names.at(1), "xmin");
  EXPECT_EQ(numbered.face_tag_names.at(3), "xmax");
  EXPECT_EQ(numbered.face_tag_names.at(2), "bc_2");
}

}  // namespace
}  // namespace dtm
