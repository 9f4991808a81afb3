// Bricked layers (format 8.0, spec/FORMAT.md §3.5) and decoding a region
// from them (§4.1): the region is exactly the whole level's cells that meet
// the box, whatever the box, and reads only the chunks around it.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <filesystem>
#include <random>
#include <thread>

#include "codec/blocks/block_runs.h"
#include "codec/bricks/brick_index_encoder.h"
#include "codec/bricks/bricks.h"
#include "codec/encode.h"
#include "codec/region_decode.h"
#include "core/reference_shape.h"
#include "mesh/carving.h"
#include "mesh/predicates.h"
#include "test_support.h"
#include "thread_ranks.h"
#include "tools/formats/input.h"

namespace dtm {
namespace {

// Levels built in blocks of about this many points: a 10k-point model has
// seams between blocks at every level but the coarsest.
constexpr uint64_t kSmallBlocks = 1500;

EncodeOptions bricked_options(uint64_t brick_points, uint64_t block_points = kSmallBlocks) {
  EncodeOptions options;
  options.box = 256;
  options.dmax = 2;
  options.bricks = true;
  options.brick_points = brick_points;
  options.block_points = block_points;
  return options;
}

std::vector<uint8_t> bricked_stream(const std::string& model, uint64_t brick_points, bool cell_hashes = false,
                                    RankExchange* exchange = nullptr, EncodeReport* report = nullptr) {
  const InputMesh in = read_input(test::data_path(model + ".node"));
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  EncodeOptions options = bricked_options(brick_points);
  options.cell_hashes = cell_hashes;
  options.exchange = exchange;
  auto encoded = encode(input, options);
  EXPECT_TRUE(encoded.ok()) << encoded.status().message();
  if (encoded.ok() && report) *report = encoded->report;
  return encoded.ok() ? encoded->bytes : std::vector<uint8_t>{};
}

using test::ThreadRanks;

// The grid box of the level's points.
GridBox bounds(std::span<const GridPoint> points) {
  GridBox b{{INT64_MAX, INT64_MAX, INT64_MAX}, {INT64_MIN, INT64_MIN, INT64_MIN}};
  for (const GridPoint& p : points) {
    const int64_t c[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], c[a]), b.hi[a] = std::max(b.hi[a], c[a]);
  }
  return b;
}

void expect_same_region(const RegionMesh& got, const RegionMesh& want, const std::string& what) {
  EXPECT_EQ(got.cells.size(), want.cells.size()) << what;
  EXPECT_TRUE(got.cells == want.cells) << what;
  // Each cell positively oriented, as the whole level's are written.
  size_t inside_out = 0;
  for (const auto& c : got.cells)
    inside_out += orientation(got.points[c[0]], got.points[c[1]], got.points[c[2]], got.points[c[3]]) <= 0;
  EXPECT_EQ(inside_out, 0u) << what;
  EXPECT_TRUE(got.points == want.points) << what;
  EXPECT_TRUE(got.vertex_ids == want.vertex_ids) << what;
  EXPECT_TRUE(got.vertex_levels == want.vertex_levels) << what;
  ASSERT_EQ(got.fields.size(), want.fields.size()) << what;
  for (size_t f = 0; f < got.fields.size(); ++f)
    EXPECT_TRUE(got.fields[f].bits == want.fields[f].bits)
        << what << ", field " << got.fields[f].description.name;
  EXPECT_TRUE(got.cell_regions == want.cell_regions) << what;
  ASSERT_EQ(got.cell_fields.size(), want.cell_fields.size()) << what;
  for (size_t f = 0; f < got.cell_fields.size(); ++f)
    EXPECT_TRUE(got.cell_fields[f].bits == want.cell_fields[f].bits)
        << what << ", cell array " << got.cell_fields[f].description.name;
}

TEST(BrickIndex, RoundTripsAndRefusesWhatDoesNotAddUp) {
  std::vector<BrickChunk> chunks = {{3, 10, 20, 5, 0, 0xDEADBEEF}, {9, 0, 0, 7, 0, 1}, {63, 4, 6, 0, 0, 2}};
  const std::vector<uint8_t> index = write_brick_index(chunks, {});
  std::vector<BrickChunk> back;
  ASSERT_TRUE(parse_brick_index(index, 2, 14, 14, 38, kFlagCarvingCorrections, 0, back).ok());
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[1].brick, 9u);
  EXPECT_EQ(back[1].offset, 25u);
  EXPECT_EQ(back[2].points_before, 10u);
  EXPECT_EQ(back[0].checksum, 0xDEADBEEFu);
  EXPECT_FALSE(parse_brick_index(index, 2, 14, 15, 38, kFlagCarvingCorrections, 0, back)
                   .ok());  // points do not add up
  EXPECT_FALSE(
      parse_brick_index(index, 2, 14, 14, 39, kFlagCarvingCorrections, 0, back).ok());  // nor the bytes
  EXPECT_FALSE(parse_brick_index(index, 1, 14, 14, 38, kFlagCarvingCorrections, 0, back)
                   .ok());  // brick 63 is outside depth 1's 8
  for (size_t cut = 0; cut < index.size(); ++cut)
    EXPECT_FALSE(
        parse_brick_index(std::span(index).first(cut), 2, 14, 14, 38, kFlagCarvingCorrections, 0, back).ok())
        << cut;
  // The sections the stream's flags allow: carving bytes only with
  // carving_corrections, value bytes in every chunk of points with values.
  EXPECT_FALSE(parse_brick_index(index, 2, 14, 14, 38, 0, 0, back).ok());
  EXPECT_FALSE(parse_brick_index(index, 2, 14, 14, 38, kFlagCarvingCorrections | kFlagValues, 0, back).ok());
  std::vector<BrickChunk> valued = chunks;
  valued[0].value_bytes = 3;
  valued[2].value_bytes = 2;
  const uint16_t both = kFlagCarvingCorrections | kFlagValues;
  EXPECT_TRUE(parse_brick_index(write_brick_index(valued, {}), 2, 14, 14, 43, both, 0, back).ok());
  EXPECT_FALSE(
      parse_brick_index(write_brick_index(valued, {}), 2, 14, 14, 43, kFlagCarvingCorrections, 0, back).ok());
  valued[1].value_bytes = 1;  // values in a chunk without points
  EXPECT_FALSE(parse_brick_index(write_brick_index(valued, {}), 2, 14, 14, 44, both, 0, back).ok());
  // 15.0's region bytes, listed only with the stream's flag regions.
  std::vector<BrickChunk> regioned = chunks;
  regioned[1].region_bytes = 6;
  const uint16_t regions = kFlagCarvingCorrections | kFlagRegions;
  ASSERT_TRUE(
      parse_brick_index(write_brick_index(regioned, {.regions = true}), 2, 14, 14, 44, regions, 0, back)
          .ok());
  EXPECT_EQ(back[1].region_bytes, 6u);
  EXPECT_EQ(back[2].offset, 38u);
  EXPECT_FALSE(parse_brick_index(write_brick_index(regioned, {.regions = true}), 2, 14, 14, 44,
                                 kFlagCarvingCorrections, 0, back)
                   .ok());
  EXPECT_FALSE(parse_brick_index(write_brick_index(chunks, {}), 2, 14, 14, 38, regions, 0, back).ok());
  // 16.0's cell value bytes, listed only in level 0's index with the
  // stream's flag cell_data.
  std::vector<BrickChunk> celled = chunks;
  celled[2].cell_value_bytes = 5;
  celled[2].cell_value_checksum = 0xC0FFEE;
  const uint16_t cell_data = kFlagCarvingCorrections | kFlagCellData;
  const std::vector<uint8_t> with_cells = write_brick_index(celled, index_fields(cell_data, 0));
  ASSERT_TRUE(parse_brick_index(with_cells, 2, 14, 14, 43, cell_data, 0, back).ok());
  EXPECT_EQ(back[2].cell_value_bytes, 5u);
  EXPECT_EQ(back[2].cell_value_checksum, 0xC0FFEEu);
  celled[0].cell_value_checksum = 1;  // a checksum of no cell values
  EXPECT_FALSE(parse_brick_index(write_brick_index(celled, index_fields(cell_data, 0)), 2, 14, 14, 43,
                                 cell_data, 0, back)
                   .ok());
  EXPECT_FALSE(parse_brick_index(with_cells, 2, 14, 14, 43, cell_data, 1, back).ok());
  EXPECT_FALSE(parse_brick_index(with_cells, 2, 14, 14, 43, kFlagCarvingCorrections, 0, back).ok());
  EXPECT_TRUE(index_fields(cell_data, 1).cell_values == false);
  chunks[1].carving_bytes = 0;  // an empty chunk is not listed
  EXPECT_FALSE(
      parse_brick_index(write_brick_index(chunks, {}), 2, 14, 14, 31, kFlagCarvingCorrections, 0, back).ok());
}

TEST(BrickGeometry, BricksMeetingABoxCoverIt) {
  const GridBox box{{5, 17, 0}, {40, 18, 63}};
  GridBox covered;
  const std::vector<uint64_t> bricks = bricks_meeting(box, 6, 2, &covered);  // 16-wide bricks of a 64 grid
  EXPECT_EQ(bricks.size(), 3u * 1u * 4u);
  EXPECT_EQ(covered.lo, (std::array<int64_t, 3>{0, 16, 0}));
  EXPECT_EQ(covered.hi, (std::array<int64_t, 3>{47, 31, 63}));
  for (uint64_t b : bricks) {
    const GridBox k = brick_box(b, 6, 2);
    EXPECT_TRUE(k.lo[0] <= box.hi[0] && k.hi[0] >= box.lo[0] && k.lo[1] <= box.hi[1] && k.hi[1] >= box.lo[1]);
  }
  EXPECT_TRUE(bricks_meeting({{64, 0, 0}, {70, 5, 5}}, 6, 2).empty());  // off the grid
}

TEST(BlockPlan, SplitsWherePointsCrowdUntilEveryBlockIsBounded) {
  // A dense cluster in one corner, sparse points elsewhere: the cluster's
  // blocks are deeper than the rest, none holds more than the bound unless
  // it is at the deepest allowed, none could have been left whole with its
  // sibling (the two would hold more than the bound), and the blocks are
  // disjoint boxes in Morton order covering every point once.
  constexpr int kQbits = 10;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int32_t> anywhere(0, 1023), corner(0, 63);
  std::vector<MortonCode> codes;
  for (int i = 0; i < 2000; ++i)
    codes.push_back(morton_encode({anywhere(rng), anywhere(rng), anywhere(rng)}, kQbits));
  for (int i = 0; i < 6000; ++i)
    codes.push_back(morton_encode({corner(rng), corner(rng), corner(rng)}, kQbits));
  std::sort(codes.begin(), codes.end());
  codes.erase(std::unique(codes.begin(), codes.end()), codes.end());
  for (const int max_depth : {2, 6}) {
    const BlockPlan plan = plan_blocks(codes, kQbits, max_depth, 300, 3);
    ASSERT_EQ(plan.first.size(), plan.blocks.size() + 1);
    EXPECT_EQ(plan.first.front(), 0u);
    EXPECT_EQ(plan.first.back(), codes.size());
    int shallowest = 3 * max_depth, deepest = 0;
    for (size_t k = 0; k < plan.blocks.size(); ++k) {
      const size_t count = plan.first[k + 1] - plan.first[k];
      EXPECT_GT(count, 0u);
      EXPECT_TRUE(count <= 300 || plan.bits[k] == 3 * max_depth) << k;
      shallowest = std::min(shallowest, plan.bits[k]);
      deepest = std::max(deepest, plan.bits[k]);
      const GridBox box = plan.box(k, kQbits);
      for (size_t i = plan.first[k]; i < plan.first[k + 1]; ++i)
        EXPECT_TRUE(box.contains(morton_decode(codes[i], kQbits)));
      // The box is the prefix's: every grid point in it has the prefix,
      // and its volume is 2^(3 qbits - bits) grid points.
      const int free = 3 * kQbits - plan.bits[k];
      for (const std::array<int64_t, 3>& corner : {box.lo, box.hi})
        EXPECT_EQ(static_cast<uint64_t>(
                      morton_encode({static_cast<int32_t>(corner[0]), static_cast<int32_t>(corner[1]),
                                     static_cast<int32_t>(corner[2])},
                                    kQbits) >>
                      free),
                  plan.blocks[k]);
      EXPECT_EQ((box.hi[0] - box.lo[0] + 1) * (box.hi[1] - box.lo[1] + 1) * (box.hi[2] - box.lo[2] + 1),
                int64_t{1} << free);
      // Its parent (one bit fewer) holds more than the bound.
      if (plan.bits[k] > 0) {
        const uint64_t parent = plan.blocks[k] >> 1;
        size_t held = 0;
        for (const MortonCode c : codes) held += static_cast<uint64_t>(c >> (free + 1)) == parent;
        EXPECT_GT(held, 300u) << k;
      }
      if (k > 0) {
        EXPECT_LE(plan.rank[k - 1], plan.rank[k]);
      }
    }
    EXPECT_LT(shallowest, deepest);  // adaptive: the cluster's blocks are deeper
    EXPECT_EQ(plan.rank.back(), 2);
  }
}

// A level of fewer blocks than ranks goes to the rank given the fewest
// points so far, so that the coarse levels (one block each) do not all
// fall to the same rank; a level of many blocks keeps its Morton runs.
TEST(BlockPlan, LevelsOfFewBlocksGoToTheLeastLoadedRank) {
  const auto plan_of = [](std::vector<size_t> first, int ranks) {
    BlockPlan p;
    p.first = std::move(first);
    for (size_t k = 0; k + 1 < p.first.size(); ++k) p.blocks.push_back(k), p.bits.push_back(3);
    assign_ranks(p, ranks);
    return p;
  };
  RankLoads loads(4);
  BlockPlan many = plan_of({0, 100, 200, 300, 400, 500, 600, 700, 1000}, 4);
  const std::vector<int> runs = many.rank;
  loads.balance(many);
  EXPECT_EQ(many.rank, runs);
  EXPECT_EQ(std::vector<uint64_t>(loads.points().begin(), loads.points().end()),
            (std::vector<uint64_t>{200, 300, 200, 300}));
  // One block a level: the least loaded rank each time (the lowest on a
  // tie), where assign_ranks would give every one to the middle rank.
  std::vector<int> given;
  for (size_t points : {150, 120, 90, 60, 30}) {
    BlockPlan one = plan_of({0, points}, 4);
    EXPECT_EQ(one.rank[0], 2);
    loads.balance(one);
    given.push_back(one.rank[0]);
  }
  EXPECT_EQ(given, (std::vector<int>{0, 2, 1, 3, 2}));
}

TEST(BrickedStream, DecodesToTheEncodersMeshesAtEveryLevel) {
  const std::vector<uint8_t> bytes = bricked_stream("hand_10k", 64, true);
  StreamHeader h;
  ASSERT_TRUE(parse_header(bytes, h).ok());
  EXPECT_EQ(h.version_major, 8);
  EXPECT_TRUE(h.flags & kFlagBricks);
  ProgressiveDecoder decoder;
  int verified = 0;
  ASSERT_TRUE(decoder
                  .feed(bytes,
                        [&](const ProgressiveDecoder& d, const DecodedLevel& l) {
                          ASSERT_TRUE(l.cell_hash.has_value());
                          const auto cells = d.carved_cells();
                          EXPECT_EQ(cell_hash_sum(d.points(), cells), *l.cell_hash) << l.level;
                          // No kept cell above the level's bound.
                          double largest = 0;
                          for (const auto& c : cells)
                            largest = std::max(largest, carving_radius(d.points(), c));
                          EXPECT_LE(largest, l.kept_radius) << l.level;
                          ++verified;
                        })
                  .ok());
  EXPECT_EQ(verified, h.level_count);
  // Several bricks per finer layer; kept_radius at least alpha (§3.5).
  const StreamSummary s = scan_stream(bytes);
  ASSERT_TRUE(s.status.ok());
  EXPECT_GT(s.layers.back().header.brick_depth, 0);
  for (const auto& l : s.layers) EXPECT_GE(l.header.kept_radius, l.header.alpha) << l.header.level;
}

// A graded mesh with its tetrahedra (hand_10k: its coarse inside's cells
// are far above the kept radius its mean spacing gives): level 0's kept
// radius is raised and the blocks made larger (spec/HIERARCHY.md §6.5),
// decisions every rank must take alike. The same bytes on 1, 2 and 3
// ranks; the stream decodes with its cell hashes, level 0 with the cells
// the encoder reported.
TEST(BrickedStream, AGradedMeshsRaisedKeptRadiusGivesTheSameBytesOnAnyNumberOfRanks) {
  const std::string dir = ::testing::TempDir() + "/graded_ranks";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(test::data_path("hand_10k.node"), dir + "/hand_10k.node",
                             std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(test::data_path("cells/hand_10k.ele"), dir + "/hand_10k.ele",
                             std::filesystem::copy_options::overwrite_existing);
  const InputMesh in = read_input(dir + "/hand_10k.node");
  ASSERT_FALSE(in.tets.empty());
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  EncodeOptions options = bricked_options(64, 2000);
  options.cell_hashes = true;
  const auto alone = encode(input, options);
  ASSERT_TRUE(alone.ok()) << alone.status().message();
  const EncodeReport& report = alone->report;
  EXPECT_GT(report.level0_kept_radius, 2 * report.level0_spacing_kept_radius);
  EXPECT_GE(report.levels.size(), 3u);
  ProgressiveDecoder decoder;
  ASSERT_TRUE(decode_stream(alone->bytes, decoder).ok());
  EXPECT_EQ(decoder.carved_cells().size(), report.levels[0].stats.tetrahedra);
  for (int ranks : {2, 3}) {
    ThreadRanks all(ranks);
    std::vector<std::vector<uint8_t>> made(static_cast<size_t>(ranks));
    std::vector<std::thread> threads;
    for (int r = 0; r < ranks; ++r)
      threads.emplace_back([&, r] {
        ThreadRanks::Rank rank(all, r);
        EncodeOptions on_rank = options;
        on_rank.exchange = &rank;
        const auto encoded = encode(input, on_rank);
        if (encoded.ok()) made[static_cast<size_t>(r)] = encoded->bytes;
      });
    for (auto& t : threads) t.join();
    for (int r = 0; r < ranks; ++r)
      EXPECT_TRUE(made[static_cast<size_t>(r)] == alone->bytes) << ranks << " ranks, rank " << r;
  }
}

// The levels are built block by block, each block's part a function of its
// region only: one process, or 2 or 3 ranks sharing the blocks, write the
// same bytes. On ranks, each holds a part of the reference, and a block's
// work asks what only the ranks together know (bunny_10k's blocks ask):
// the ranks answer while they work and the pass that asked runs again, or,
// where the exchange cannot (an MPI without threads), they answer in their
// next exchange and the block's work runs again.
TEST(BrickedStream, TheSameBytesForAnyNumberOfRanks) {
  for (const std::string model : {"hand_10k", "bunny_10k"}) {
    SCOPED_TRACE(model);
    const std::vector<uint8_t> alone = bricked_stream(model, 64, true);
    ASSERT_FALSE(alone.empty());
    for (const bool at_once : {true, false}) {
      for (int ranks : {1, 2, 3}) {
        SCOPED_TRACE(at_once ? "answered while working" : "answered in the exchanges");
        ThreadRanks all(ranks);
        all.answer_while_working(at_once);
        std::vector<std::vector<uint8_t>> made(static_cast<size_t>(ranks));
        std::vector<EncodeReport> reports(static_cast<size_t>(ranks));
        std::vector<std::thread> threads;
        for (int r = 0; r < ranks; ++r)
          threads.emplace_back([&, r] {
            ThreadRanks::Rank rank(all, r);
            made[static_cast<size_t>(r)] =
                bricked_stream(model, 64, true, &rank, &reports[static_cast<size_t>(r)]);
          });
        for (auto& t : threads) t.join();
        for (int r = 0; r < ranks; ++r) {
          const EncodeReport& report = reports[static_cast<size_t>(r)];
          EXPECT_TRUE(made[static_cast<size_t>(r)] == alone) << ranks << " ranks, rank " << r;
          EXPECT_EQ(report.reference_questions, reports[0].reference_questions);
          EXPECT_EQ(report.reference_questions_at_once, reports[0].reference_questions_at_once);
        }
        const EncodeReport& report = reports[0];
        if (ranks == 1) {
          EXPECT_EQ(report.reference_question_runs + report.reference_questions_at_once, 0u);
        } else if (model == "bunny_10k" && at_once) {
          // Every question answered in the pass that asked it: no block run again.
          EXPECT_GT(report.reference_questions_at_once, 0u) << ranks;
          EXPECT_EQ(report.reference_question_runs, 0u) << ranks;
        } else if (model == "bunny_10k") {
          EXPECT_GT(report.reference_questions, 0u) << ranks;
          EXPECT_GT(report.reference_question_runs, 0u) << ranks;
          EXPECT_EQ(report.reference_questions_at_once, 0u) << ranks;
        }
      }
    }
  }
}

// Blocks built side by side on a process's threads (run_blocks' at_once),
// one at a time or more at once than there are cores: the same stream.
TEST(BrickedStream, TheSameBytesWhateverBlocksAreBuiltAtOnce) {
  for (const std::string model : {"hand_10k", "bunny_10k"}) {
    SCOPED_TRACE(model);
    const InputMesh in = read_input(test::data_path(model + ".node"));
    EncodeInput input;
    input.points = in.points;
    input.tetrahedra = in.tets;
    std::vector<uint8_t> first;
    for (int at_once : {1, 3, 8}) {
      EncodeOptions options = bricked_options(64);
      options.blocks_at_once = at_once;
      auto encoded = encode(input, options);
      ASSERT_TRUE(encoded.ok()) << encoded.status().message();
      if (first.empty()) {
        first = encoded->bytes;
        ASSERT_FALSE(first.empty());
      }
      EXPECT_TRUE(encoded->bytes == first) << at_once << " blocks at once";
    }
  }
}

// A block a neighbour put points back in is checked where they came
// (parts_near, check_part) rather than built again when its last build was
// clean: the stream must be the one building it again gives. elephant_10k
// in blocks of 1,500 points has both kinds.
TEST(BrickedStream, ABlockCheckedWhereANeighbourChangedItGivesTheBytesOfOneBuiltAgain) {
  const InputMesh in = read_input(test::data_path("elephant_10k.node"));
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  EncodeOptions options = bricked_options(64, kSmallBlocks);
  const auto checked = encode(input, options);
  ASSERT_TRUE(checked.ok()) << checked.status().message();
  options.check_parts = false;
  const auto built = encode(input, options);
  ASSERT_TRUE(built.ok()) << built.status().message();
  EXPECT_GT(checked->report.blocks_checked_in_parts, 0u);
  EXPECT_EQ(built->report.blocks_checked_in_parts, 0u);
  EXPECT_EQ(built->report.blocks_built_again,
            checked->report.blocks_built_again + checked->report.blocks_checked_in_parts);
  EXPECT_TRUE(checked->bytes == built->bytes);
}

// A level whose choice fits in one block is built in one, and its
// analysis takes the build's tetrahedralization and the solid's verdicts
// on its cells (BlockBuild::mesh) rather than making them again: the
// stream must be the one making them again gives. elephant_10k in blocks
// of 1,500 points has levels of several blocks and levels of one.
TEST(BrickedStream, ALevelAnalysedFromItsBuildGivesTheBytesOfOneMadeAgain) {
  const InputMesh in = read_input(test::data_path("elephant_10k.node"));
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  EncodeOptions options = bricked_options(64, kSmallBlocks);
  const auto reused = encode(input, options);
  ASSERT_TRUE(reused.ok()) << reused.status().message();
  options.reuse_build_mesh = false;
  const auto made = encode(input, options);
  ASSERT_TRUE(made.ok()) << made.status().message();
  EXPECT_GT(reused->report.levels_analysed_from_build, 0u);
  EXPECT_EQ(made->report.levels_analysed_from_build, 0u);
  EXPECT_TRUE(reused->bytes == made->bytes);
}

// A caller that wants no vertex_of_input (meshenc) gets the same bytes
// without it; handed its plan, the encoder frees the plan's map from input
// points (4 bytes an input point held while the levels are built). Bricked
// and whole levels, with and without values.
TEST(BrickedStream, WithoutVertexOfInputTheSameBytesAndThePlansMapFreed) {
  const InputMesh in = read_input(test::data_path("bunny_10k.node"));
  std::vector<double> height(in.points.size());
  for (size_t i = 0; i < height.size(); ++i) height[i] = in.points[i].z;
  for (const bool bricks : {true, false})
    for (const bool with_values : {false, true}) {
      EncodeInput input;
      input.points = in.points;
      input.tetrahedra = in.tets;
      const std::vector<EncodeInput::Field> fields = {{"height", ValueType::kF64, 1, height}};
      if (with_values) input.fields = fields;
      EncodeOptions options = bricked_options(64, 2000);
      options.bricks = bricks;
      StatusOr<EncodePlan> plan = plan_encoding(input, options);
      ASSERT_TRUE(plan.ok()) << plan.status().message();
      const auto kept = encode(input, options, *plan);  // the plan kept
      ASSERT_TRUE(kept.ok()) << kept.status().message();
      EXPECT_EQ(kept->vertex_of_input.size(), in.points.size());
      EXPECT_EQ(plan->quantized.input_to_point.size(), in.points.size());
      options.vertex_of_input = false;
      const auto without = encode(input, options, std::move(*plan));
      ASSERT_TRUE(without.ok()) << without.status().message();
      EXPECT_TRUE(without->bytes == kept->bytes) << bricks << with_values;
      EXPECT_TRUE(without->vertex_of_input.empty());
      EXPECT_EQ(without->report.input_points, in.points.size());
      EXPECT_TRUE(plan->quantized.input_to_point.empty());  // NOLINT(bugprone-use-after-move): freed, as said
    }
}

// Every level within D_max of the input's boundary both ways, measured on
// the decoded levels against the whole input (not block by block): the
// checks the blocks make at their own places add up to the whole level's,
// seams included.
TEST(BrickedStream, EveryDecodedLevelKeepsTheShapeAcrossBlockSeams) {
  for (const std::string model : {"bunny_10k", "elephant_10k", "hand_10k"}) {
    const InputMesh in = read_input(test::data_path(model + ".node"));
    EncodeInput input;
    input.points = in.points;
    input.tetrahedra = in.tets;
    const auto encoded = encode(input, bricked_options(64, 500));
    ASSERT_TRUE(encoded.ok()) << encoded.status().message();
    const double dmax = encoded->report.dmax / encoded->report.grid.step;
    ProgressiveDecoder finest;
    ASSERT_TRUE(decode_stream(encoded->bytes, finest).ok());
    // The input's tetrahedra over the decoder's vertices (without them,
    // level 0's carving is the reference).
    std::vector<std::array<uint32_t, 4>> reference;
    if (in.tets.empty()) reference = finest.carved_cells();
    for (const auto& t : in.tets) {
      std::array<uint32_t, 4> v;
      for (int i = 0; i < 4; ++i) v[i] = encoded->vertex_of_input[t[i]];
      std::array<uint32_t, 4> s = v;
      std::sort(s.begin(), s.end());
      if (std::adjacent_find(s.begin(), s.end()) == s.end()) reference.push_back(v);
    }
    const std::vector<GridPoint> points(finest.points().begin(), finest.points().end());
    const int levels = static_cast<int>(encoded->report.levels.size());
    double level0_quality = 0;
    for (int level = 0; level < levels; ++level) {
      DecoderOptions o;
      o.stop_after_level = level;
      ProgressiveDecoder d(o);
      ASSERT_TRUE(decode_stream(encoded->bytes, d).ok());
      ReferenceShape shape(points, reference);
      const ShapeMeasurement m = shape.distance(d.carved_cells(), points);
      EXPECT_LE(m.to_level.max, dmax * (1 + 1e-9)) << model << " level " << level;
      EXPECT_LE(m.to_reference.max, dmax * (1 + 1e-9)) << model << " level " << level;
      const LevelStats& s = encoded->report.levels[static_cast<size_t>(level)].stats;
      if (level == 0) level0_quality = s.avg_min_solid_angle;
      // The quality floor (0.85 of level 0's average) holds block by block,
      // each block against level 0's average there: over the whole level
      // within a few percent of it.
      EXPECT_GE(s.avg_min_solid_angle, 0.85 * 0.97 * level0_quality) << model << " level " << level;
      std::printf(
          "%s level %d: %llu vertices, shape %.3f / %.3f of D_max %.3f, quality %.4f (%.3f of level 0's)\n",
          model.c_str(), level, static_cast<unsigned long long>(s.vertices), m.to_level.max,
          m.to_reference.max, dmax, s.avg_min_solid_angle, s.avg_min_solid_angle / level0_quality);
    }
    EXPECT_GE(levels, 3) << model;
  }
}

TEST(BrickedStream, RegionIsTheWholeLevelFilteredToTheBox) {
  for (const std::string model : {"bunny_10k", "fandisk_11k", "hand_10k"}) {
    const std::vector<uint8_t> bytes = bricked_stream(model, 8);
    StreamHeader h;
    ASSERT_TRUE(parse_header(bytes, h).ok());
    std::mt19937 rng(7);
    bool some_box_read_less = false;
    for (int level = 0; level < h.level_count; ++level) {
      DecoderOptions o;
      o.stop_after_level = level;
      ProgressiveDecoder whole(o);
      ASSERT_TRUE(decode_stream(bytes, whole).ok());
      const GridBox all = bounds(whole.points());
      std::vector<GridBox> boxes;
      for (int i = 0; i < 6; ++i) {  // random boxes of 1% to 10% of the volume
        GridBox b;
        const double share = std::uniform_real_distribution<double>(0.2, 0.47)(rng);
        for (int a = 0; a < 3; ++a) {
          const int64_t w = static_cast<int64_t>(share * static_cast<double>(all.hi[a] - all.lo[a]));
          b.lo[a] = std::uniform_int_distribution<int64_t>(all.lo[a], all.hi[a] - w)(rng);
          b.hi[a] = b.lo[a] + w;
        }
        boxes.push_back(b);
      }
      GridBox corner = all;  // at the mesh's edge: a corner of its bounds
      for (int a = 0; a < 3; ++a) corner.lo[a] = all.hi[a] - (all.hi[a] - all.lo[a]) / 5;
      boxes.push_back(corner);
      boxes.push_back(all);                              // the whole level
      boxes.push_back({{-50, -50, -50}, {-1, -1, -1}});  // off the grid: nothing
      boxes.push_back({{all.lo[0], all.lo[1], all.lo[2]}, {all.lo[0], all.lo[1], all.lo[2]}});  // one point
      for (size_t i = 0; i < boxes.size(); ++i) {
        MemorySource source(bytes);
        const auto got = decode_region(source, boxes[i], level);
        ASSERT_TRUE(got.ok()) << got.status().message();
        const RegionMesh want = region_of(whole, boxes[i]);
        expect_same_region(*got, want,
                           model + " level " + std::to_string(level) + " box " + std::to_string(i));
        EXPECT_TRUE(got->bricked);
        // The one-point box at a corner of the level reads the chunks near it only.
        if (level == 0 && i + 1 == boxes.size()) some_box_read_less = got->bytes_read < bytes.size() * 3 / 5;
      }
      EXPECT_GT(region_of(whole, all).cells.size(), 0u);
    }
    EXPECT_TRUE(some_box_read_less) << model << ": a one-point region read most of the stream";
  }
}

// Values in chunks (§3.5): every decoded value is the input's (lossless) or
// within its bound (lossy), and a region's values, read from its chunks
// alone, are the whole decode's.
TEST(BrickedStream, RegionsCarryTheValuesOfTheWholeDecode) {
  const InputMesh in = read_input(test::data_path("bunny_10k.node"));
  std::vector<double> smooth, noisy;
  std::mt19937 rng(3);
  for (const InputPoint& p : in.points) {
    smooth.push_back(std::sin(p.x * 20) + p.y * p.z);
    noisy.push_back(std::uniform_real_distribution<double>(0, 1)(rng));
  }
  const std::vector<EncodeInput::Field> fields = {{"smooth", ValueType::kF64, 1, smooth},
                                                  {"noisy", ValueType::kF32, 1, noisy}};
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  input.fields = fields;
  EncodeOptions options = bricked_options(64);
  options.field_errors["noisy"] = 0.01;
  const auto encoded = encode(input, options);
  ASSERT_TRUE(encoded.ok()) << encoded.status().message();
  const std::vector<uint8_t>& bytes = encoded->bytes;
  StreamHeader h;
  ASSERT_TRUE(parse_header(bytes, h).ok());
  EXPECT_TRUE(h.flags & kFlagValues);
  ProgressiveDecoder whole;
  ASSERT_TRUE(decode_stream(bytes, whole).ok());
  ASSERT_EQ(whole.fields().size(), 2u);
  for (size_t i = 0; i < in.points.size(); ++i) {
    const uint32_t v = encoded->vertex_of_input[i];
    EXPECT_EQ(whole.fields()[0].value(v, 0), smooth[i]) << i;
    EXPECT_LE(std::abs(whole.fields()[1].value(v, 0) - static_cast<float>(noisy[i])), 0.01) << i;
  }
  const GridBox all = bounds(whole.points());
  for (int level : {0, 2}) {
    DecoderOptions o;
    o.stop_after_level = level;
    ProgressiveDecoder d(o);
    ASSERT_TRUE(decode_stream(bytes, d).ok());
    for (int i = 0; i < 4; ++i) {
      GridBox b;
      for (int a = 0; a < 3; ++a) {
        const int64_t w = (all.hi[a] - all.lo[a]) / 3;
        b.lo[a] = std::uniform_int_distribution<int64_t>(all.lo[a], all.hi[a] - w)(rng);
        b.hi[a] = b.lo[a] + w;
      }
      MemorySource source(bytes);
      const auto got = decode_region(source, b, level);
      ASSERT_TRUE(got.ok()) << got.status().message();
      ASSERT_EQ(got->fields.size(), 2u);
      expect_same_region(*got, region_of(d, b),
                         "level " + std::to_string(level) + " box " + std::to_string(i));
    }
  }
  // Damage in a chunk's values is that chunk's (its checksum), the others decode.
  std::vector<uint8_t> damaged = bytes;
  const StreamSummary s = scan_stream(bytes);
  ASSERT_TRUE(s.status.ok());
  const LayerSummary& finest = s.layers.back();
  const uint64_t index_at = finest.offset + kBrickedLayerHeaderSize;
  std::vector<BrickChunk> chunks;
  ASSERT_TRUE(parse_brick_index(std::span(bytes).subspan(index_at, finest.header.index_bytes),
                                finest.header.brick_depth, h.grid.qbits, finest.header.new_vertices,
                                finest.header.chunk_bytes, h.flags, finest.header.level, chunks)
                  .ok());
  const BrickChunk& victim = chunks[chunks.size() / 3];
  ASSERT_GT(victim.value_bytes, 0u);
  damaged[index_at + finest.header.index_bytes + victim.offset + victim.size() - 1] ^= 0x40;
  ProgressiveDecoder hurt;
  EXPECT_EQ(decode_stream(damaged, hurt).code(), StatusCode::kCorrupt);
}

// Pieces (one per MPI rank): every cell of the level in exactly one piece.
TEST(BrickedStream, PiecesPartitionTheLevel) {
  const std::vector<uint8_t> bytes = bricked_stream("hand_10k", 8);
  StreamHeader h;
  ASSERT_TRUE(parse_header(bytes, h).ok());
  for (int level : {0, 2}) {
    DecoderOptions o;
    o.stop_after_level = level;
    ProgressiveDecoder whole(o);
    ASSERT_TRUE(decode_stream(bytes, whole).ok());
    std::vector<std::array<uint32_t, 4>> want = whole.carved_cells();
    for (auto& c : want) std::sort(c.begin(), c.end());
    std::sort(want.begin(), want.end());
    for (int pieces : {1, 2, 3, 4, 7}) {
      std::vector<std::array<uint32_t, 4>> got;
      uint64_t read = 0;
      for (int piece = 0; piece < pieces; ++piece) {
        MemorySource source(bytes);
        const auto p = decode_piece(source, level, piece, pieces);
        ASSERT_TRUE(p.ok()) << p.status().message();
        for (auto c : p->cells) {
          for (uint32_t& v : c) {
            EXPECT_EQ(whole.points()[p->vertex_ids[v]], p->points[v]);
            v = p->vertex_ids[v];
          }
          std::sort(c.begin(), c.end());
          got.push_back(c);
        }
        read = std::max(read, p->bytes_read);
      }
      std::sort(got.begin(), got.end());
      EXPECT_TRUE(got == want) << "level " << level << ", " << pieces << " pieces: " << got.size()
                               << " cells, " << want.size() << " in the level";
      if (pieces >= 4 && level == 0) {
        EXPECT_LT(read, bytes.size()) << "a piece read the whole stream";
      }
    }
  }
  MemorySource source(bytes);
  EXPECT_FALSE(decode_piece(source, 0, 4, 4).ok());
  // Bytes after level 0's layer: refused by a piece as by the whole decoder
  // (spec/FORMAT.md §4), not read past; a coarser level's piece does not
  // reach them.
  std::vector<uint8_t> trailing = bytes;
  trailing.insert(trailing.end(), {1, 2, 'j', 'u', 'n', 'k'});
  MemorySource with_junk(trailing);
  const auto refused = decode_piece(with_junk, 0, 0, 2);
  ASSERT_EQ(refused.status().code(), StatusCode::kCorrupt);
  EXPECT_NE(refused.status().message().find("trailing data after the last layer"), std::string::npos)
      << refused.status().message();
  MemorySource coarser(trailing);
  EXPECT_TRUE(decode_piece(coarser, 2, 0, 2).ok());
  // The whole decoder asked for level 0 (meshdec --level 0) refuses them too.
  DecoderOptions to_level_0;
  to_level_0.stop_after_level = 0;
  ProgressiveDecoder whole_to_0(to_level_0);
  EXPECT_EQ(decode_stream(trailing, whole_to_0).code(), StatusCode::kCorrupt);
}

// --box sets the units the encoder measures in; a bricked stream, like a
// whole one, keeps the input's: level 0 decodes with the input's bounding
// box, to within half a grid step.
TEST(BrickedStream, KeepsTheInputsUnitsWhateverTheBoxSays) {
  EncodeReport report;
  const std::vector<uint8_t> bytes = bricked_stream("bunny_10k", 256, false, nullptr, &report);
  ProgressiveDecoder decoder;
  ASSERT_TRUE(decode_stream(bytes, decoder).ok());
  const Grid& grid = decoder.header().grid;
  ASSERT_GT(report.scale, 10.0);
  EXPECT_NEAR(grid.step * report.scale, report.grid.step, 1e-12 * report.grid.step);
  const auto box_of = [](const auto& points, const auto& position) {
    std::array<double, 6> b{DBL_MAX, DBL_MAX, DBL_MAX, -DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (const auto& p : points) {
      const InputPoint q = position(p);
      const double c[3] = {q.x, q.y, q.z};
      for (int a = 0; a < 3; ++a) b[a] = std::min(b[a], c[a]), b[a + 3] = std::max(b[a + 3], c[a]);
    }
    return b;
  };
  const auto decoded = box_of(decoder.points(), [&](const GridPoint& p) { return grid.to_input(p); });
  const auto input =
      box_of(read_input(test::data_path("bunny_10k.node")).points, [](const InputPoint& p) { return p; });
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(decoded[i], input[i], grid.step * 0.5 * (1 + 1e-9)) << i;
}

// A box whose corners are decoded vertices' coordinates holds those
// vertices, whatever the rounding of origin + k step divided back.
TEST(BrickedStream, ABoxCornerOnADecodedVertexHoldsIt) {
  Grid grid;
  grid.qbits = 14;
  grid.origin = {-4.958475, -0.003149, -3.729833};
  grid.step = 9.90733 / 16383;
  for (int64_t k = 0; k < 16384; k += 7) {
    const InputPoint p = grid.to_input({static_cast<int32_t>(k), static_cast<int32_t>(16383 - k), 5});
    const GridBox b = grid_box_of(grid, {p.x, p.y, p.z}, {p.x, p.y, p.z});
    ASSERT_EQ(b.lo[0], k);
    ASSERT_EQ(b.hi[0], k);
    ASSERT_EQ(b.lo[1], 16383 - k);
    ASSERT_EQ(b.hi[1], 16383 - k);
    ASSERT_EQ(b.lo[2], 5);
  }
  // Between grid points: the points inside only.
  const GridBox between =
      grid_box_of(grid, {grid.origin[0] + 2.5 * grid.step, 0, 0}, {grid.origin[0] + 2.6 * grid.step, 1, 1});
  EXPECT_GT(between.lo[0], between.hi[0]);
}

TEST(BrickedStream, RegionOfAStreamNotBrickedIsDecodedWhole) {
  const InputMesh in = read_input(test::data_path("bunny_10k.node"));
  EncodeInput input;
  input.points = in.points;
  input.tetrahedra = in.tets;
  EncodeOptions options;
  options.box = 256;
  const auto encoded = encode(input, options);
  ASSERT_TRUE(encoded.ok());
  ProgressiveDecoder whole;
  ASSERT_TRUE(decode_stream(encoded->bytes, whole).ok());
  const GridBox all = bounds(whole.points());
  GridBox half = all;
  half.hi[0] = (all.lo[0] + all.hi[0]) / 2;
  MemorySource source(encoded->bytes);
  const auto got = decode_region(source, half, 0);
  ASSERT_TRUE(got.ok()) << got.status().message();
  EXPECT_FALSE(got->bricked);
  EXPECT_EQ(got->bytes_read, encoded->bytes.size());
  expect_same_region(*got, region_of(whole, half), "not bricked");
}

// A damaged chunk is reported by the decodes that read it, and only by them.
TEST(BrickedStream, ADamagedChunkFailsTheRegionsThatReadIt) {
  std::vector<uint8_t> bytes = bricked_stream("bunny_10k", 64);
  const StreamSummary s = scan_stream(bytes);
  ASSERT_TRUE(s.status.ok());
  const LayerSummary& finest = s.layers.back();
  const LayerHeader& lh = finest.header;
  const uint64_t index_at = finest.offset + kBrickedLayerHeaderSize;
  std::vector<BrickChunk> chunks;
  ASSERT_TRUE(parse_brick_index(std::span(bytes).subspan(index_at, lh.index_bytes), lh.brick_depth,
                                s.header.grid.qbits, lh.new_vertices, lh.chunk_bytes, s.header.flags,
                                lh.level, chunks)
                  .ok());
  ASSERT_GT(chunks.size(), 4u);
  const BrickChunk& victim = chunks[chunks.size() / 2];
  bytes[index_at + lh.index_bytes + victim.offset + victim.size() / 2] ^= 0x10;

  ProgressiveDecoder whole;
  const Status status = decode_stream(bytes, whole);
  EXPECT_EQ(status.code(), StatusCode::kCorrupt);
  EXPECT_NE(status.message().find("chunk checksum mismatch"), std::string::npos) << status.message();
  // (It names the damaged chunk's first byte in the stream, not only its layer's.)
  const std::string chunk_at =
      "its chunk at byte " + std::to_string(index_at + lh.index_bytes + victim.offset) + ":";
  EXPECT_NE(status.message().find(chunk_at), std::string::npos) << status.message();
  EXPECT_EQ(whole.finest_level(), 1);  // the coarser levels stand

  const GridBox inside = brick_box(victim.brick, s.header.grid.qbits, lh.brick_depth);
  MemorySource source(bytes);
  const auto touching = decode_region(source, inside, 0);
  ASSERT_FALSE(touching.ok());
  EXPECT_NE(touching.status().message().find("brick " + std::to_string(victim.brick)), std::string::npos)
      << touching.status().message();
  // The level and its layer's offset, as the whole decoder names them, and the chunk's.
  EXPECT_NE(touching.status().message().find("level 0 at byte " + std::to_string(finest.offset)),
            std::string::npos)
      << touching.status().message();
  EXPECT_NE(touching.status().message().find(chunk_at), std::string::npos) << touching.status().message();
  // A box far from it: a corner of the grid away from the victim.
  const int64_t top = (int64_t{1} << s.header.grid.qbits) - 1;
  GridBox far;
  for (int a = 0; a < 3; ++a) {
    const bool low = inside.lo[a] > top / 2;
    far.lo[a] = low ? 0 : top - top / 16;
    far.hi[a] = low ? top / 16 : top;
  }
  const auto away = decode_region(source, far, 0);
  EXPECT_TRUE(away.ok()) << away.status().message();
}

// Every prefix: the whole levels it holds, never a crash; a region of a level
// the prefix lacks is a truncation.
TEST(BrickedStream, EveryPrefixDecodesItsWholeLevels) {
  const std::vector<uint8_t> bytes = bricked_stream("bunny_10k", 64);
  const StreamSummary s = scan_stream(bytes);
  for (size_t cut = 0; cut < bytes.size(); cut += 1 + cut / 50) {
    const std::span<const uint8_t> prefix = std::span(bytes).first(cut);
    ProgressiveDecoder d;
    const Status status = decode_stream(prefix, d);
    EXPECT_TRUE(status.code() == StatusCode::kTruncated || status.code() == StatusCode::kNeedMoreInput ||
                (status.code() == StatusCode::kNotDtm && cut < kMagic.size()))
        << cut << ": " << status.message();
    size_t whole = 0;  // layers that end at or before the cut
    for (const LayerSummary& l : s.layers)
      if (l.offset + l.size() <= cut) ++whole;
    EXPECT_EQ(d.levels().size(), whole) << cut;
    MemorySource source(prefix);
    const auto region = decode_region(source, {{0, 0, 0}, {1 << 20, 1 << 20, 1 << 20}}, 0);
    EXPECT_FALSE(region.ok()) << cut;
  }
}

}  // namespace
}  // namespace dtm
