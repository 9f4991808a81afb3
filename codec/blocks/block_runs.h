// The blocks of a level and how the ranks of a run share them
// (codec/blocks/bricked_encoder.h): which rank builds which block, the one
// exchange every phase ends with, and the bytes a block's results travel in
// (between this program's own ranks: written and read without checks).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "codec/blocks/block_levels.h"
#include "codec/stream/layer_coder.h"
#include "common/byte_io.h"
#include "common/exchange.h"
#include "common/status.h"

namespace dtm {

// The blocks of one level: non-empty boxes of the grid halved one Morton
// bit at a time, in Morton order, and the rank that builds each
// (contiguous runs of about equal point counts).
struct BlockPlan {
  std::vector<uint64_t> blocks;  // each block's Morton prefix: the first `bits` bits of its points' codes
  std::vector<int> bits;         // of each prefix (3 x the depth of an octree node)
  std::vector<size_t> first;     // of each block's points in the level's Morton order; one more at the end
  std::vector<int> rank;
  GridBox box(size_t k, int qbits) const;
};
// The grid's box halved (across x, y, z in turn: one Morton bit each
// time, so that every block is a box and a block of 3d bits an octree node
// of depth d) until no block holds more than `max_points` of the level's
// points or its prefix has 3 `max_depth` bits: the largest block, and so
// what building it holds in memory, is bounded by the points wherever they
// crowd, not by their average; halving rather than splitting in eight
// leaves blocks of between about half and all of `max_points`, whose
// halos add less. `codes`: the level's Morton codes, ascending.
BlockPlan plan_blocks(std::span<const MortonCode> codes, int qbits, int max_depth, uint64_t max_points,
                      int ranks);
// Ranks for a plan's blocks, given their `first` points: contiguous runs of
// about equal point counts.
void assign_ranks(BlockPlan& plan, int ranks);
// The ranks' shares of the work over a run's plans (the same on every
// rank): a plan of fewer blocks than ranks (the coarse levels, one block
// each) would leave its blocks to the same middle ranks level after level;
// each of its blocks goes instead to the rank given the fewest points so
// far. Other plans keep assign_ranks' runs (the reference's shares follow
// Morton order too). Either way the plan's points are counted. `prefer`:
// the rank a plan of one block goes to (-1: the least loaded).
class RankLoads {
 public:
  explicit RankLoads(int ranks) : points_(static_cast<size_t>(std::max(1, ranks)), 0) {}
  void balance(BlockPlan& plan, int prefer = -1);
  std::span<const uint64_t> points() const { return points_; }

 private:
  std::vector<uint64_t> points_;  // per rank, of the blocks it was given
};

// Runs `work` on every block of `plan` this rank builds, each result
// serialized by the work, and returns every block's bytes, indexed by
// block, on every rank. A failure on any rank (a Status, or an exception,
// which would otherwise leave the other ranks waiting in the exchange) is
// every rank's: `status` says it (the first block's, in block order).
// `at_once` > 1: up to that many of this rank's blocks are worked on side
// by side, each on its share of the threads (common/threads.h), so `work`
// must be safe to run on several blocks at once; the results are the same.
std::vector<std::vector<uint8_t>> run_blocks(
    const BlockPlan& plan, RankExchange& exchange,
    const std::function<StatusOr<std::vector<uint8_t>>(size_t)>& work, Status& status, int at_once = 1);

void put(ByteWriter& w, std::span<const uint32_t> v);
void put(ByteWriter& w, std::span<const uint8_t> v);
void put(ByteWriter& w, const DistanceSums& d);

// Reads what put() and ByteWriter wrote (the input is this program's own).
class BlockReader {
 public:
  explicit BlockReader(std::span<const uint8_t> bytes) : r_(bytes) {}
  uint8_t u8();
  uint32_t u32();
  uint64_t u64();
  double f64();
  std::vector<uint32_t> u32s();
  std::vector<uint8_t> bytes();
  DistanceSums sums();
  bool done() const { return r_.remaining() == 0; }

 private:
  ByteReader r_;
};

std::vector<uint8_t> serialize(const BlockAnalysis& a);
BlockAnalysis deserialize_analysis(std::span<const uint8_t> bytes);

}  // namespace dtm
