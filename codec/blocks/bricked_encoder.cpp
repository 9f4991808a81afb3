#include "codec/blocks/bricked_encoder.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#if defined(__linux__) && !defined(__EMSCRIPTEN__)
#include <unistd.h>
#endif

#include "codec/blocks/block_levels.h"
#include "codec/blocks/block_runs.h"
#include "codec/blocks/bricked_stream_writer.h"
#include "codec/blocks/level_merge.h"
#include "codec/blocks/rank_reference.h"
#include "codec/blocks/reference_share.h"
#include "codec/bricks/bricks.h"
#include "codec/sections/face_coder.h"
#include "common/byte_io.h"
#include "common/parallel_for.h"
#include "common/release.h"
#include "common/threads.h"
#include "core/nearest_spacing.h"

namespace dtm {
namespace {

// How far from a block's box the work on a level of that kept radius
// looks (block_levels.h): every cell it owns that the level may keep has
// its circumsphere within 2 kept radii of the box, a surface triangle
// within D_max of a reference vertex in the box its cells' within D_max
// more; so a point put back farther changes nothing a build checks there
// (build()). Grid units.
int64_t reach_for(double kept_radius, double dmax) {
  return static_cast<int64_t>(std::ceil(2 * kept_radius + dmax)) + 1;
}
// The halo of its region: one unit past the reach, so what a build's
// checks see lies in the region.
int64_t halo_for(double kept_radius, double dmax) { return reach_for(kept_radius, dmax) + 1; }
// alpha of a bricked level (spec/HIERARCHY.md §6.5): this many times the
// mean distance from a vertex to its nearest neighbour.
constexpr double kAlphaPerSpacing = 1.5;
// A coarser level keeps no cell of circumradius above this many times the
// finer level's alpha (its kept_radius: about twice its own alpha, a level
// having about 2^(1/3) times the finer one's spacing); level 0, twice its own.
// A region reader decodes the bricks within twice the largest kept
// circumradius of its box (codec/region_decode.h): without the bound a few
// nearly flat kept cells (0.1-0.3% of a coarse level's, circumradii up to
// 10^4 alpha) would make every region the whole level.
constexpr double kKeptRadiusPerFinerAlpha = 2.5;
constexpr double kKeptRadiusOfLevel0 = 2.0;
// Level 0 analysed again with a larger kept radius at most this many times
// (run()); the raised radius this much above the largest cell it must keep,
// so that a cell at the bound is kept however the product rounds.
constexpr int kKeptRadiusRounds = 3;
constexpr double kKeptRadiusMargin = 1e-6;
// Beyond D_max: by more than a rounding of the distance.
constexpr double kBeyondDmax = 1e-9;
// With a raised kept radius, the blocks' regions hold at most about this
// many times the level's points (fewer_blocks_for()). Not applied otherwise:
// bunny_1m's blocks of 2^18 points have regions of about 2.5 times theirs.
constexpr double kRegionsPerLevel = 3;
// Blocks built at once unless told: one per thread, as many as a quarter of
// this process's share of the machine's memory holds at about 1 KB a block
// point (bunny_1m's blocks of up to 228,640 points took about 230 MiB each),
// so that a process with many threads does not run out of memory on a
// machine with little.
int default_blocks_at_once(uint64_t block_points) {
  const int threads = thread_count();
#if defined(__linux__) && !defined(__EMSCRIPTEN__)
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const unsigned machine_threads = std::max(1u, std::thread::hardware_concurrency());
  if (pages > 0 && page > 0) {
    const double memory = static_cast<double>(pages) * static_cast<double>(page) * threads / machine_threads;
    const double fit = memory / 4 / (1024.0 * static_cast<double>(block_points));
    return std::clamp(static_cast<int>(std::min(fit, double{1 << 20})), 1, threads);
  }
#endif
  return threads;
}

// Whether one block (Morton prefix, its bits) holds the other.
bool nested(uint64_t a, int bits_a, uint64_t b, int bits_b) {
  return bits_a <= bits_b ? (b >> (bits_b - bits_a)) == a : (a >> (bits_a - bits_b)) == b;
}

// The level's quality floor over each level-0 block: average_quality_floor
// times level 0's average there (a block of a coarser level takes the
// blocks of level 0 inside it, or around it).
struct QualityFloors {
  std::vector<uint64_t> blocks;
  std::vector<int> bits;
  std::vector<double> sum;
  std::vector<uint64_t> count;
  double factor = 0, whole = 0;

  double floor(uint64_t block, int bits_of_block) const {
    if (factor <= 0) return 0;
    double s = 0;
    uint64_t c = 0;
    for (size_t i = 0; i < blocks.size(); ++i)
      if (nested(blocks[i], bits[i], block, bits_of_block)) s += sum[i], c += count[i];
    return factor * (c > 0 ? s / static_cast<double>(c) : whole);
  }
};

class BrickedEncoder {
 public:
  BrickedEncoder(const BrickedEncodeInput& in, const BrickedEncodeOptions& o, RankExchange& exchange)
      : in_(in),
        o_(o),
        x_(exchange),
        q_(in.grid.qbits),
        reference_(in.points, q_, exchange, in.voxels, o.hierarchy.on_phase),
        at_once_(o.blocks_at_once > 0 ? o.blocks_at_once : default_blocks_at_once(o.block_points)),
        cells_need_tets_(in.cell_values && !in.reference_tets.empty()) {
    if (x_.size() > 1)
      reference_.set_in_parts(in.reference_tets, in.reference_regions, in.regions.size(), in.share,
                              [this] { tets_done(); });
    else if (!in.reference_tets.empty())
      reference_.set_whole(in.reference_tets, in.reference_regions);
    // With cell data, level 0's blocks find each kept cell's input
    // tetrahedron: the tetrahedra are read until level 0's cells are coded,
    // once level 1 is built (on ranks too, where every rank is given them
    // all: encode_bricked()). Made once the reference is, not beside it.
    if (cells_need_tets_) cell_sources_.emplace(in.points, in.reference_tets);
    tets_done();
    // Made once the reference is: not held (5 bytes a point, 47 MiB at
    // bunny_10m, on every rank) beside the tetrahedra while the reference's
    // boundary and solid are found, the largest of a rank's phases before
    // the levels.
    report_phase(o_.hierarchy.on_phase, "the points by Morton code");
    index_.emplace(in.points, q_);
    level_of_.assign(in.points.size(), 0);
  }

  StatusOr<BrickedEncoding> run(const std::function<void(const LevelStats&)>& on_level);

 private:
  double removal_share() const {
    return o_.hierarchy.removal_share > 0 ? o_.hierarchy.removal_share : kDefaultRemovalShare;
  }
  void phase(int level, const std::string& what) const {
    report_phase(o_.hierarchy.on_phase, "level " + std::to_string(level) + ": " + what);
  }
  // Tells the caller, once, that the reference's tetrahedra are read no more
  // (not while level 0's cell values are still to find: cells_done()).
  void tets_done() {
    if (cells_need_tets_) return;
    if (in_.reference_tets_done && !tets_done_) in_.reference_tets_done();
    tets_done_ = true;
  }
  // Level 0's cell values are coded: the tetrahedra by vertex are held no
  // more, nor the tetrahedra.
  void cells_done() {
    cell_sources_.reset();
    cells_need_tets_ = false;
    tets_done();
  }
  BlockRegion region_of(const BlockPlan& plan, size_t k, int level, int64_t halo) const;
  // Level `level`'s plan again in blocks of 8, 64, ... times its points
  // while the blocks' regions (grown by the halo of `kept_radius`) hold
  // more than kRegionsPerLevel times the level's points: a raised kept
  // radius (run()) makes halos that span most of the level, and each block
  // would do most of the level's work again. Sets the blocks built at once
  // for the blocks' size. `codes`: room for index_->level()'s.
  // `block_points`: the plan's, raised with it.
  void fewer_blocks_for(int level, double kept_radius, size_t level_points, int brick_depth,
                        uint64_t& block_points, BlockPlan& plan, std::vector<MortonCode>& codes);
  StatusOr<double> level_alpha(std::span<const uint32_t> ids, const BlockPlan& plan);
  Status analyse(int level, const BlockPlan& plan, int64_t halo, const BlockAnalysisOptions& options,
                 std::vector<BlockAnalysis>& out);
  // The coarser level of `level`: chosen (the blocks' choice in `analysis`),
  // built and repaired; once more removing less where that fails. False
  // when neither is good enough (`level` is then the coarsest); else
  // level_of_ says the coarser level and built_stats_ its figures.
  // `halo`: the analysis's (a choice made again), `build_halo` the build's.
  // `block_points`: the most points the plan let a block hold (a choice
  // of no more is built in one block).
  StatusOr<bool> coarser_level(int level, size_t finer, const BlockPlan& plan, uint64_t block_points,
                               int64_t halo, int64_t build_halo, BlockAnalysisOptions options,
                               const std::vector<BlockAnalysis>& analysis, std::span<const uint32_t> boundary,
                               double kept_radius, const QualityFloors& floors);
  // The coarser level from the choice: builds, repairs, and merges until no
  // block's region changes. Sets coarser_ (per grid point).
  Status build(int level, const BlockPlan& plan, int64_t halo, double kept_radius,
               const QualityFloors& floors, uint64_t& broken, bool& quality_met, int& rounds);
  // The base layer is one chunk of depth 0 (§3.5): its carving (and
  // regions) over the whole coarsest level, on rank 0, sent to every rank.
  Status base_carving(int level, BrickedLevel& out);
  // The stream of the levels built (codec/blocks/bricked_stream_writer.h),
  // the coarsest one's carving made one chunk first.
  StatusOr<BrickedEncoding> write(std::vector<BrickedLevel>& levels);

  const BrickedEncodeInput& in_;
  const BrickedEncodeOptions& o_;
  RankExchange& x_;
  RankLoads loads_{x_.size()};  // which rank builds the blocks of a level of few
  int q_;
  std::optional<MortonIndex> index_;  // made once the reference is (the constructor)
  std::vector<uint8_t> level_of_;     // per grid point: the coarsest level that holds it
  // The reference (none before level 0 is built, when level 0 is the reference).
  RankReference reference_;
  SurfaceRecord record_;  // the finer level's
  std::vector<std::pair<uint32_t, double>> reference_squared_;
  std::vector<uint8_t> coarser_;  // per grid point: in the level being built
  LevelStats built_stats_;        // the coarser level's figures made while building it
  bool last_ = false;             // the coarser level is to be the coarsest
  uint64_t reference_boundary_vertices_ = 0;
  bool tets_done_ = false;
  std::optional<CellSourceIndex> cell_sources_;  // with cell data, until level 0's cells are coded
  int at_once_;                                  // blocks built side by side (run_blocks)
  bool cells_need_tets_;                         // cell_sources_ is (or is to be) made of the tetrahedra
  // Blocks a neighbour changed: built again, checked in parts (build()).
  uint64_t blocks_built_again_ = 0, blocks_checked_in_parts_ = 0;
  // Level 0's kept radius from its spacing, as used, and the cells of the
  // solid it still drops (run()).
  double level0_spacing_kept_radius_ = 0, level0_kept_radius_ = 0;
  uint64_t level0_cells_dropped_ = 0;
  bool level0_radius_raised() const { return level0_kept_radius_ > level0_spacing_kept_radius_; }
  // The tetrahedralization a build in one block left (on the rank that
  // built it): the coarser level's whole, which its analysis, one block
  // too, takes rather than making it again (analyse()).
  struct HeldMesh {
    std::vector<uint32_t> ids;  // its vertices' grid ids, ascending
    MadeMesh mesh;
  };
  std::optional<HeldMesh> held_;
  int built_in_one_by_ = -1;  // the rank that built the coarser level in one block; -1: not in one
  uint64_t levels_analysed_from_build_ = 0;
};

void BrickedEncoder::fewer_blocks_for(int level, double kept_radius, size_t level_points, int brick_depth,
                                      uint64_t& block_points, BlockPlan& plan,
                                      std::vector<MortonCode>& codes) {
  const int64_t halo = halo_for(kept_radius, o_.hierarchy.dmax);
  bool planned_again = false;
  while (plan.blocks.size() > 1 && block_points < (uint64_t{1} << 40)) {
    uint64_t held = 0;
    for (size_t k = 0; k < plan.blocks.size(); ++k)
      held += index_->inside(plan.box(k, q_).grown(halo, q_), level_of_, level).size();
    if (static_cast<double>(held) <= kRegionsPerLevel * static_cast<double>(level_points)) break;
    block_points *= 8;
    index_->level(level_of_, level, codes);
    plan = plan_blocks(codes, q_, brick_depth, block_points, x_.size());
    release(codes);
    planned_again = true;
  }
  // Only the plan that runs counts in the ranks' loads.
  if (planned_again) loads_.balance(plan);
  at_once_ = o_.blocks_at_once > 0 ? o_.blocks_at_once : default_blocks_at_once(block_points);
}

BlockRegion BrickedEncoder::region_of(const BlockPlan& plan, size_t k, int level, int64_t halo) const {
  BlockRegion b;
  b.owned = plan.box(k, q_);
  b.region = b.owned.grown(halo, q_);
  b.ids = index_->inside(b.region, level_of_, level);
  b.points = gather(in_.points, b.ids);
  return b;
}

StatusOr<double> BrickedEncoder::level_alpha(std::span<const uint32_t> ids, const BlockPlan& plan) {
  if (o_.hierarchy.alpha.kind == AlphaKind::kFixed) return o_.hierarchy.alpha.fixed_value;
  // Each vertex's nearest neighbour, found among the whole level (every
  // rank holds its points), summed block by block.
  const NearestSpacing nearest(in_.points, ids);
  Status status = Status::Ok();
  const auto sums = run_blocks(
      plan, x_,
      [&](size_t k) -> StatusOr<std::vector<uint8_t>> {
        const size_t first = plan.first[k], count = plan.first[k + 1] - first;
        std::vector<double> d(count, 0);
        parallel_for(
            count, [&](size_t i) { d[i] = nearest.nearest(first + i); }, 4096);
        double sum = 0;
        for (double v : d) sum += v;
        ByteWriter w;
        w.f64(sum);
        return w.take();
      },
      status, at_once_);
  DTM_RETURN_IF_ERROR(status);
  double total = 0;
  for (const auto& s : sums) total += BlockReader(s).f64();
  return kAlphaPerSpacing * total / static_cast<double>(ids.size());
}

Status BrickedEncoder::analyse(int level, const BlockPlan& plan, int64_t halo,
                               const BlockAnalysisOptions& options, std::vector<BlockAnalysis>& out) {
  // What `out` held (the finer level's blocks, their choices and surfaces)
  // is not held while these blocks work.
  release(out);
  Status status = Status::Ok();
  auto results = reference_.run_carving(
      plan,
      [&](size_t k, const Solid* solid) -> StatusOr<std::vector<uint8_t>> {
        const BlockRegion block = region_of(plan, k, level, halo);
        // (The faces' pass measures nothing: no boundary for its shape.)
        std::optional<BlockReference> reference =
            reference_.for_region(block.region, solid, !options.faces_only);
        // The build's tetrahedralization of these very points, when one
        // block built them (one block here: no other thread reads held_),
        // taken once (a run asking the ranks about the reference runs again).
        std::optional<MadeMesh> made;
        if (plan.blocks.size() == 1 && reference && held_ && held_->ids == block.ids) {
          made = std::move(held_->mesh);
          held_.reset();
          ++levels_analysed_from_build_;
        }
        DTM_ASSIGN_OR_RETURN(BlockAnalysis a, analyse_block(block, reference ? &*reference : nullptr, options,
                                                            made ? &*made : nullptr));
        return serialize(a);
      },
      status, at_once_);
  held_.reset();
  DTM_RETURN_IF_ERROR(status);
  out.clear();
  for (auto& r : results) {
    out.push_back(deserialize_analysis(r));
    release(r);
  }
  // The blocks' triangulations, made on one thread each in CGAL's
  // sequential type, came from malloc's arenas (one per thread), which
  // keep what is freed: handed back once the level's blocks are done, not
  // after each block (slower, tools/tool_main.h). A graded mesh of 325k
  // vertices held 120 MiB more after level 0's first round without.
  give_back_free_heap();
  return Status::Ok();
}

Status BrickedEncoder::build(int level, const BlockPlan& plan, int64_t halo, double kept_radius,
                             const QualityFloors& floors, uint64_t& broken, bool& quality_met, int& rounds) {
  held_.reset();
  built_in_one_by_ = plan.blocks.size() == 1 ? plan.rank[0] : -1;
  LevelBounds bounds;
  bounds.dmax = o_.hierarchy.dmax;
  bounds.kept_radius = kept_radius;
  // Per block: its last result (region size as left), broken places,
  // quality, rounds; the blocks still to build.
  std::vector<uint64_t> left(plan.blocks.size(), 0), block_broken(plan.blocks.size(), 0);
  std::vector<uint8_t> met(plan.blocks.size(), 1), to_build(plan.blocks.size(), 1);
  std::vector<int> block_rounds(plan.blocks.size(), 0);
  // Per block, for a check where it changed instead of a build
  // (check_part()): whether its last build was clean, the quality's sum and
  // cells then, the pass it was last built or checked in and what it put
  // back then; per pass, every point put back in it.
  std::vector<uint8_t> clean(plan.blocks.size(), 0);
  std::vector<double> quality_sum(plan.blocks.size(), 0);
  std::vector<uint64_t> quality_cells(plan.blocks.size(), 0);
  std::vector<int> last_pass(plan.blocks.size(), 0);
  std::vector<std::vector<uint32_t>> own_back(plan.blocks.size());
  std::vector<std::vector<uint32_t>> added;
  // What a block's checks see: its box grown by 2 kept radii and D_max.
  // A point put back farther away changes none of the cells it owns that
  // the level keeps (their circumspheres lie within 2 kept radii of the box),
  // so none of its surface triangles nor the quality of its cells, and it
  // makes no surface within D_max of a reference vertex of the box.
  const int64_t reach = reach_for(kept_radius, o_.hierarchy.dmax);
  const auto seen = [&](size_t k) { return plan.box(k, q_).grown(reach, q_); };
  // Block k's check where it changed, on the points put back since its last
  // build that it sees: clean and the quality met (PartCheck), or nullopt:
  // build it again.
  struct Checked {
    double quality_sum = 0;
    uint64_t quality_cells = 0;
  };
  const auto check_again = [&](size_t k, int pass, const BlockRegion& fine, const Solid* solid,
                               const LevelBounds& b) -> StatusOr<std::optional<Checked>> {
    if (!clean[k] || !o_.check_parts) return std::optional<Checked>{};
    const GridBox box = plan.box(k, q_), sees = seen(k);
    std::vector<uint32_t> fresh;
    for (int p = last_pass[k]; p < pass; ++p)
      for (uint32_t id : added[static_cast<size_t>(p)])
        if (sees.contains(in_.points[id]) &&
            (p != last_pass[k] || !std::binary_search(own_back[k].begin(), own_back[k].end(), id)))
          fresh.push_back(id);
    std::sort(fresh.begin(), fresh.end());
    fresh.erase(std::unique(fresh.begin(), fresh.end()), fresh.end());
    // Many: a seam's worth of checks would cost what building again does.
    if (fresh.size() > 4096) return std::optional<Checked>{};
    const std::vector<GridBox> parts = parts_near(fresh, in_.points, box, reach, q_);
    double volume = 0;
    const auto size = [](const GridBox& g) {
      double v = 1;
      for (int a = 0; a < 3; ++a) v *= static_cast<double>(g.hi[a] - g.lo[a] + 1);
      return v;
    };
    for (const GridBox& g : parts) volume += size(g.grown(halo, q_));
    if (volume > 0.5 * size(fine.region)) return std::optional<Checked>{};
    Checked out{quality_sum[k], quality_cells[k]};
    for (const GridBox& g : parts) {
      BlockRegion part;
      part.owned = g;
      part.region = g.grown(halo, q_);
      part.ids = index_->inside(part.region, level_of_, level);
      part.points = gather(in_.points, part.ids);
      std::vector<uint8_t> before(part.ids.size()), now(part.ids.size());
      for (size_t i = 0; i < part.ids.size(); ++i) {
        now[i] = coarser_[part.ids[i]];
        before[i] = now[i] && !std::binary_search(fresh.begin(), fresh.end(), part.ids[i]);
      }
      std::optional<BlockReference> reference = reference_.for_region(part.region, solid);
      // A part the check cannot make (its coarser points too few or flat,
      // where the block's are not): build the block again, which can. (A
      // reference in parts that asks the ranks is answered first, as for a
      // build: reference_questions.h.)
      const StatusOr<PartCheck> c = check_part(part, before, now, record_, reference_squared_, *reference, b);
      if (!c.ok() && c.status().code() == StatusCode::kNeedMoreInput) return c.status();
      if (!c.ok() || !c->clean) return std::optional<Checked>{};
      out.quality_sum += c->quality_sum_now - c->quality_sum_before;
      out.quality_cells = out.quality_cells + c->quality_cells_now - c->quality_cells_before;
    }
    // The quality as a build would sum it, but for rounding: too near the
    // floor to tell, build.
    if (b.quality_floor > 0 && out.quality_cells > 0) {
      const double q = out.quality_sum / static_cast<double>(out.quality_cells);
      if (q < b.quality_floor * (1 + 1e-9) + 1e-12) return std::optional<Checked>{};
    }
    return std::optional<Checked>{out};
  };
  for (int pass = 0;; ++pass) {
    phase(level + 1,
          pass == 0 ? "building the blocks" : "checking or building again where a neighbour put points back");
    Status status = Status::Ok();
    const auto results = reference_.run_carving(
        plan,
        [&](size_t k, const Solid* solid) -> StatusOr<std::vector<uint8_t>> {
          ByteWriter w;
          if (!to_build[k]) {
            w.u8(0);
            return w.take();
          }
          const BlockRegion fine = region_of(plan, k, level, halo);
          LevelBounds b = bounds;
          b.quality_floor = floors.floor(plan.blocks[k], plan.bits[k]);
          const GridBox checked = seen(k);
          // The block's result, as the merge below reads it.
          const auto result = [&](uint64_t in_sight, const BlockBuild& r, std::span<const uint32_t> back,
                                  bool checked_in_parts) {
            w.u8(1);
            w.u64(in_sight);
            w.u64(r.broken);
            w.u8(r.quality_met ? 1 : 0);
            w.u32(static_cast<uint32_t>(r.rounds));
            put(w, back);
            w.u8(r.clean ? 1 : 0);
            w.f64(r.quality_sum);
            w.u64(r.quality_cells);
            w.u8(checked_in_parts ? 1 : 0);
            return w.take();
          };
          if (pass > 0) {
            DTM_ASSIGN_OR_RETURN(const std::optional<Checked> same, check_again(k, pass, fine, solid, b));
            if (same) {
              // What building it again would give: nothing put back,
              // nothing broken, clean.
              uint64_t in_sight = 0;
              for (uint32_t id : fine.ids) in_sight += coarser_[id] && checked.contains(in_.points[id]);
              BlockBuild r;
              r.clean = true;
              r.quality_sum = same->quality_sum;
              r.quality_cells = same->quality_cells;
              return result(in_sight, r, {}, true);
            }
          }
          std::vector<uint8_t> keep(fine.ids.size());
          for (size_t i = 0; i < keep.size(); ++i) keep[i] = coarser_[fine.ids[i]];
          std::optional<BlockReference> reference = reference_.for_region(fine.region, solid);
          DTM_ASSIGN_OR_RETURN(BlockBuild built,
                               build_block(fine, keep, record_, reference_squared_, *reference, b));
          // One block: the coarser level's whole tetrahedralization, kept
          // for its analysis (no other thread writes held_).
          if (plan.blocks.size() == 1 && o_.reuse_build_mesh)
            held_ = HeldMesh{built.vertices, std::move(built.mesh)};
          // What it put back (the rest was chosen already), and how much of
          // the coarser level its checks saw.
          std::vector<uint32_t> back;
          uint64_t in_sight = 0;
          for (uint32_t id : built.vertices) {
            if (!coarser_[id]) back.push_back(id);
            in_sight += checked.contains(in_.points[id]);
          }
          return result(in_sight, built, back, false);
        },
        status, at_once_);
    DTM_RETURN_IF_ERROR(status);
    added.emplace_back();
    for (size_t k = 0; k < results.size(); ++k) {
      BlockReader r(results[k]);
      if (!r.u8()) continue;
      left[k] = r.u64();
      block_broken[k] = r.u64();
      met[k] = r.u8();
      block_rounds[k] = std::max(block_rounds[k], static_cast<int>(r.u32()));
      own_back[k] = r.u32s();  // ascending: built.vertices are
      for (uint32_t id : own_back[k]) coarser_[id] = 1;
      added.back().insert(added.back().end(), own_back[k].begin(), own_back[k].end());
      clean[k] = r.u8();
      quality_sum[k] = r.f64();
      quality_cells[k] = r.u64();
      last_pass[k] = pass;
      if (pass > 0) (r.u8() ? blocks_checked_in_parts_ : blocks_built_again_) += 1;
    }
    // A block that now sees more of the coarser level than it left (a
    // neighbour put points back there) is built again.
    bool again = false;
    std::vector<uint8_t> next(plan.blocks.size(), 0);
    {
      Status s2 = Status::Ok();
      const auto changed = run_blocks(
          plan, x_,
          [&](size_t k) -> StatusOr<std::vector<uint8_t>> {
            uint64_t now = 0;
            for (uint32_t id : index_->inside(seen(k), level_of_, level)) now += coarser_[id];
            return std::vector<uint8_t>{static_cast<uint8_t>(now > left[k] ? 1 : 0)};
          },
          s2, at_once_);
      DTM_RETURN_IF_ERROR(s2);
      for (size_t k = 0; k < changed.size(); ++k) next[k] = changed[k].at(0), again = again || next[k];
    }
    if (!again || pass >= 6) {
      broken = 0;
      rounds = 0;
      std::vector<BlockQuality> quality(plan.blocks.size());
      for (size_t k = 0; k < plan.blocks.size(); ++k) {
        broken += block_broken[k] + (next[k] ? 1 : 0);  // a block left unchecked counts as broken
        rounds = std::max(rounds, block_rounds[k]);
        quality[k] = {met[k] != 0, quality_sum[k], quality_cells[k],
                      floors.floor(plan.blocks[k], plan.bits[k])};
      }
      quality_met = level_quality_met(quality);
      return Status::Ok();
    }
    to_build = next;
  }
}

Status BrickedEncoder::base_carving(int level, BrickedLevel& out) {
  BlockPlan one;
  one.blocks = {0};
  one.bits = {0};
  one.first = {0, 0};
  one.rank = {0};
  BlockAnalysisOptions options;
  options.qbits = q_;
  options.alpha = out.alpha;
  options.kept_radius = out.kept_radius;
  options.brick_depth = 0;
  options.region_count = in_.regions.size();
  options.faces = in_.faces;
  options.face_tags = in_.face_tags.size();
  if (level == 0 && cell_sources_) {
    options.cell_sources = &*cell_sources_;
    options.cell_values = in_.cell_values;
  }
  std::vector<BlockAnalysis> a;
  DTM_RETURN_IF_ERROR(analyse(level, one, 0, options, a));
  out.clear_sections();
  out.take_sections(a.at(0));
  return Status::Ok();
}

StatusOr<BrickedEncoding> BrickedEncoder::run(const std::function<void(const LevelStats&)>& on_level) {
  const HierarchyOptions& h = o_.hierarchy;
  std::vector<MortonCode> codes;
  std::vector<uint32_t> ids;
  index_->level(level_of_, 0, codes);
  const int finest_depth = choose_brick_depth(codes, q_, 2 * o_.brick_points);
  QualityFloors floors;
  floors.factor = h.average_quality_floor;
  std::vector<BrickedLevel> levels;
  double next_kept_radius = 0;  // the largest circumradius the coarser level keeps
  for (int level = 0;; ++level) {
    if (level > 250) return invalid_input("more than 250 levels");
    reference_.start_level();
    index_->level(level_of_, level, codes, &ids);
    BrickedLevel out;
    out.brick_depth =
        std::min(finest_depth, choose_brick_depth(codes, q_, std::max<uint64_t>(1, o_.brick_points / 4)));
    BlockPlan plan = plan_blocks(codes, q_, out.brick_depth, o_.block_points, x_.size());
    // A level of one block built in one is analysed by the rank holding
    // its tetrahedralization (held_).
    loads_.balance(plan, built_in_one_by_);
    release(codes);  // 16 bytes a point, not held while the blocks are built
    uint64_t block_points = o_.block_points;
    phase(level, "alpha");
    DTM_ASSIGN_OR_RETURN(out.alpha, level_alpha(ids, plan));
    // The level's ids (4 bytes a point) are not held while its blocks work:
    // level_of_ says them.
    const size_t level_points = ids.size();
    release(ids);
    if (!(out.alpha > 0)) return invalid_input("the level's points do not span three dimensions");
    // kept_radius is the build's, alpha (a prediction) at most that (§3.5).
    double kept_radius = level == 0 ? kKeptRadiusOfLevel0 * out.alpha : next_kept_radius;
    out.alpha = std::min(out.alpha, kept_radius);
    const bool may_choose = !last_ && !(h.max_levels > 0 && level >= h.max_levels);

    BlockAnalysisOptions options;
    options.qbits = q_;
    options.alpha = out.alpha;
    options.brick_depth = out.brick_depth;
    options.region_count = in_.regions.size();
    options.face_tags = in_.face_tags.size();
    options.dmax = h.dmax;
    options.collect_cells = level == 0 && !reference_.has_boundary();
    if (level == 0 && cell_sources_) {
      options.cell_sources = &*cell_sources_;
      options.cell_values = in_.cell_values;
    }
    if (may_choose) options.choice = CoarseningOptions{1 - removal_share(), h.dmax};
    std::vector<BlockAnalysis> analysis;
    MergedLevel merged;
    int64_t halo = 0;
    if (level == 0) level0_spacing_kept_radius_ = kept_radius;
    for (int round = 0;; ++round) {
      // Once level 0's kept radius was raised, the blocks are made larger
      // until their regions stop holding the level many times over.
      if (level0_radius_raised() || round > 0)
        fewer_blocks_for(level, kept_radius, level_points, out.brick_depth, block_points, plan, codes);
      size_t largest = 0;
      for (size_t k = 0; k < plan.blocks.size(); ++k)
        largest = std::max(largest, plan.first[k + 1] - plan.first[k]);
      // The analysis of this level sees its own cells.
      halo = halo_for(kept_radius, h.dmax);
      options.kept_radius = kept_radius;
      // Tagged faces in the same pass where one block holds the whole
      // level, else in a pass of their own (below).
      options.faces = plan.blocks.size() == 1 ? in_.faces : nullptr;
      // One block built in one on this rank: its build's tetrahedralization
      // is taken (analyse()).
      const bool from_build = plan.blocks.size() == 1 && held_ && held_->ids.size() == level_points;
      phase(
          level,
          (from_build
               ? std::string("carving and choice in 1 block, from its build's tetrahedralization, of ")
               : "Delaunay tetrahedralization, carving and choice in " + std::to_string(plan.blocks.size()) +
                     (plan.blocks.size() == 1 ? " block of " : " blocks of at most ")) +
              std::to_string(largest) + " points");
      DTM_RETURN_IF_ERROR(analyse(level, plan, halo, options, analysis));

      // The level's figures, carving and surface record, merged in block order.
      out.stats = built_stats_;
      out.stats.level = level;
      out.stats.vertices = level_points;
      out.stats.alpha = out.alpha;
      out.cell_hash = 0;
      out.clear_sections();
      merged = merge_blocks(analysis, level, out);
      // Level 0 keeps the input's solid: where the solid holds cells above
      // the kept radius its spacing sets (a graded mesh's coarse inside,
      // whose cells are many times its fine surface's), level 0 would lack
      // them, its surface beyond D_max from the input's. The kept radius is
      // then raised to cover them, and level 0 analysed again (spec/HIERARCHY.md
      // §6.5): every block's region grows with it, and every region read.
      // Only cells thicker than D_max count: a flat cell on the solid's
      // surface may have any circumradius (hand_10k's reach 400 units in the
      // 256 box), and dropping it moves the surface by its thickness. A
      // block's largest dropped cell may be one its region makes up (a
      // circumsphere reaching past the halo), so the radius can overshoot;
      // the rounds are bounded.
      const bool beyond =
          out.stats.reference_shape && out.stats.reference_shape->both.max > h.dmax * (1 + kBeyondDmax);
      if (level > 0 || !reference_.has_boundary() || merged.dropped_thick == 0 || !beyond ||
          round == kKeptRadiusRounds || !(merged.dropped_thick_radius > kept_radius))
        break;
      kept_radius = merged.dropped_thick_radius * (1 + kKeptRadiusMargin);
    }
    out.kept_radius = kept_radius;
    if (level == 0) {
      level0_kept_radius_ = kept_radius;
      level0_cells_dropped_ = merged.dropped_thick;
    }
    // A coarser level's cells are larger than the finer level's: once level
    // 0's was raised, no coarser level's kept radius is below the finer one's.
    next_kept_radius =
        std::max(kKeptRadiusPerFinerAlpha * out.alpha, level0_radius_raised() ? kept_radius : 0.0);
    // The build of the coarser level (in this level's blocks) sees the
    // coarser level's cells.
    const int64_t build_halo = halo_for(next_kept_radius, h.dmax);
    record_ = std::move(merged.record);
    reference_squared_ = std::move(merged.reference_squared);
    if (merged.reference_boundary_vertices)
      reference_boundary_vertices_ = *merged.reference_boundary_vertices;
    if (level == 0) {
      floors.blocks = plan.blocks;
      floors.bits = plan.bits;
      for (const BlockAnalysis& a : analysis) {
        floors.sum.push_back(a.figures.quality_sum);
        floors.count.push_back(a.figures.cells);
      }
      floors.whole = out.stats.avg_min_solid_angle;
      if (!reference_.has_boundary()) {
        // Level 0's carving is the reference from now on (the solid, unless
        // the voxels are), and its surface the reference's: every distance
        // to it is 0.
        std::sort(merged.carved.begin(), merged.carved.end());
        reference_.set_whole(merged.carved);
        release(merged.carved);
        reference_squared_.clear();
      }
    }
    // The faces' tags of a level in several blocks: each block's region
    // grown by two kept radii more, so that the cell across each face its
    // bricks code is the level's (block_levels.h); apart from the analysis,
    // whose choice and build depend on its halo (the levels do not depend
    // on the tags).
    if (in_.faces && plan.blocks.size() > 1) {
      BlockAnalysisOptions faces = options;
      faces.kept_radius = kept_radius;
      faces.faces = in_.faces;
      faces.faces_only = true;
      faces.choice.reset();
      faces.collect_cells = false;
      faces.cell_sources = nullptr;
      faces.cell_values = nullptr;
      phase(level, "the tagged faces in " + std::to_string(plan.blocks.size()) + " blocks");
      std::vector<BlockAnalysis> tagged;
      DTM_RETURN_IF_ERROR(
          analyse(level, plan, halo + static_cast<int64_t>(std::ceil(2 * kept_radius)) + 1, faces, tagged));
      for (BlockAnalysis& a : tagged) out.take_faces(a);
    }
    if (on_level) on_level(out.stats);
    levels.push_back(std::move(out));
    if (!may_choose) break;
    options.cell_sources = nullptr;
    options.cell_values = nullptr;
    DTM_ASSIGN_OR_RETURN(const bool built,
                         coarser_level(level, level_points, plan, block_points, halo, build_halo, options,
                                       analysis, merged.boundary, next_kept_radius, floors));
    if (!built) break;
    // (Held until level 1 is: were level 0 the only level, its base layer
    // would code its cells' values again, write().)
    if (level == 0) cells_done();
  }
  release(coarser_);
  return write(levels);
}

StatusOr<BrickedEncoding> BrickedEncoder::write(std::vector<BrickedLevel>& levels) {
  const HierarchyOptions& h = o_.hierarchy;
  const int coarsest = static_cast<int>(levels.size()) - 1;
  if (levels[coarsest].brick_depth != 0 || levels[coarsest].carving.size() > 1 ||
      levels[coarsest].regions.size() > 1 || levels[coarsest].faces.size() > 1 ||
      levels[coarsest].cell_values.size() > 1) {
    report_phase(h.on_phase, "the base layer's carving");
    DTM_RETURN_IF_ERROR(base_carving(coarsest, levels[coarsest]));
  }
  cells_done();
  levels[coarsest].brick_depth = 0;
  // No block carves any more: the reference (this rank's part of the solid,
  // the boundary's index, and the whole boundary where a level of one block
  // was built here) and the finest surface's record are not held while the
  // stream is written.
  reference_.release_all();
  release(record_.triangles);
  release(record_.vertices);
  release(record_.reference_squared);
  release(reference_squared_);
  BrickedStreamInput stream;
  stream.points = in_.points;
  stream.grid = in_.grid;
  stream.alpha_policy = h.alpha.kind;
  stream.cell_hashes = o_.cell_hashes;
  stream.values = in_.values;
  stream.regions = in_.regions;
  stream.face_tags = in_.face_tags;
  stream.cell_values = in_.cell_values;
  stream.index = &*index_;
  stream.level_of = level_of_;
  stream.decode_order = o_.decode_order;
  stream.exchange = &x_;
  stream.on_phase = h.on_phase;
  DTM_ASSIGN_OR_RETURN(BrickedEncoding encoding, write_bricked_stream(stream, levels));
  encoding.reference_boundary_vertices = reference_boundary_vertices_;
  encoding.reference_questions = reference_.questions().questions;
  encoding.reference_question_runs = reference_.questions().runs;
  encoding.reference_questions_at_once = reference_.questions().answered_at_once;
  encoding.blocks_built_again = blocks_built_again_;
  encoding.blocks_checked_in_parts = blocks_checked_in_parts_;
  encoding.levels_analysed_from_build = levels_analysed_from_build_;
  encoding.level0_spacing_kept_radius = level0_spacing_kept_radius_;
  encoding.level0_kept_radius = level0_kept_radius_;
  encoding.level0_cells_dropped = level0_cells_dropped_;
  return encoding;
}

StatusOr<bool> BrickedEncoder::coarser_level(int level, size_t finer, const BlockPlan& plan,
                                             uint64_t block_points, int64_t halo, int64_t build_halo,
                                             BlockAnalysisOptions options,
                                             const std::vector<BlockAnalysis>& analysis,
                                             std::span<const uint32_t> boundary, double kept_radius,
                                             const QualityFloors& floors) {
  const HierarchyOptions& h = o_.hierarchy;
  const double share = removal_share();
  // The finer level: the points of level_of_ `level` or above.
  const auto in_finer = [&](size_t id) { return level_of_[id] >= level; };
  for (const double attempt : {share, kRetryShare * share}) {
    coarser_.assign(in_.points.size(), 0);
    if (attempt == share) {
      for (const BlockAnalysis& a : analysis)
        for (uint32_t id : a.chosen) coarser_[id] = 1;
    } else {
      phase(level + 1, "choosing again, fewer");
      options.choice = CoarseningOptions{1 - attempt, h.dmax};
      options.brick_depth = -1;
      options.collect_cells = false;
      std::vector<BlockAnalysis> again;
      DTM_RETURN_IF_ERROR(analyse(level, plan, halo, options, again));
      for (const BlockAnalysis& a : again)
        for (uint32_t id : a.chosen) coarser_[id] = 1;
    }
    uint64_t chosen = 0;
    for (size_t id = 0; id < coarser_.size(); ++id) chosen += in_finer(id) && coarser_[id];
    // A choice that fits in one block is built in one, over the whole
    // finer level (spec/HIERARCHY.md §6.5): its analysis, one block too,
    // then takes the build's tetrahedralization rather than making it
    // again, and no seam of the finer level's blocks is built twice. The
    // rank given the fewest points so far builds it (and so analyses it),
    // so that the coarse levels, one block each, are shared among the
    // ranks rather than each built where the finer one was analysed.
    BlockPlan whole;
    const bool in_one = chosen <= block_points;
    if (in_one) {
      whole.blocks = {0};
      whole.bits = {0};
      whole.first = {0, finer};
      whole.rank = {0};
      loads_.balance(whole);
    }
    uint64_t broken = 0;
    bool quality_met = true;
    int rounds = 0;
    DTM_RETURN_IF_ERROR(
        build(level, in_one ? whole : plan, build_halo, kept_radius, floors, broken, quality_met, rounds));
    uint64_t coarser = 0, removed_boundary = 0;
    for (size_t id = 0; id < coarser_.size(); ++id) coarser += in_finer(id) && coarser_[id];
    for (uint32_t id : boundary) removed_boundary += !coarser_[id];
    if (coarser < h.min_base_vertices) {
      held_.reset();
      return false;
    }
    if (static_cast<double>(finer - coarser) < kThinLevelShare * share * static_cast<double>(finer) ||
        !quality_met || broken > 0)
      continue;
    built_stats_ = {};
    built_stats_.removed_boundary = removed_boundary;
    built_stats_.removed_interior = finer - coarser - removed_boundary;
    built_stats_.passes = 1;
    built_stats_.chosen = chosen;
    built_stats_.put_back = coarser - chosen;
    built_stats_.repair_rounds = rounds;
    last_ = h.stop_when_boundary_is_final && removed_boundary == 0;
    for (size_t id = 0; id < coarser_.size(); ++id)
      if (in_finer(id) && coarser_[id]) level_of_[id] = static_cast<uint8_t>(level + 1);
    release(coarser_);  // level_of_ says it now
    return true;
  }
  held_.reset();
  return false;
}

}  // namespace

StatusOr<BrickedEncoding> encode_bricked(const BrickedEncodeInput& input, const BrickedEncodeOptions& options,
                                         const std::function<void(const LevelStats&)>& on_level) {
  SingleProcess alone;
  RankExchange& exchange = options.exchange ? *options.exchange : alone;
  const Status checked = [&]() -> Status {
    if (input.points.size() < 4) return invalid_input("fewer than four points make no tetrahedron");
    if (input.points.size() > (size_t{1} << 31))
      return invalid_input("bricked streams hold at most 2^31 points");
    if (options.brick_points == 0 || options.block_points == 0)
      return invalid_input("brick and block points must be positive");
    if (options.hierarchy.alpha.kind == AlphaKind::kConvexHull)
      return invalid_input("bricked layers need a finite alpha (the halo of a region is made from it)");
    if (options.hierarchy.alpha.kind == AlphaKind::kFixed && !(options.hierarchy.alpha.fixed_value > 0))
      return invalid_input("a fixed alpha must be positive");
    if (!input.reference_regions.empty()) {
      if (input.regions.size() < 2) return invalid_input("tetrahedra in regions without a table of them");
      if (input.reference_regions.size() != input.reference_tets.size())
        return invalid_input("each reference tetrahedron needs its region");
      for (uint8_t r : input.reference_regions)
        if (r == 0 || r > input.regions.size())
          return invalid_input("a tetrahedron's region is not in the table");
    } else if (input.regions.size() > 1 && !input.reference_tets.empty()) {
      // (A rank of a run may hold no tetrahedron, and the table be every rank's.)
      return invalid_input("a table of regions without the tetrahedra's");
    }
    if (!input.regions.empty()) DTM_RETURN_IF_ERROR(check_region_table(input.regions));
    if (input.cell_values && input.reference_tets.empty())
      return invalid_input("cell data without the tetrahedra it belongs to");
    if (input.faces && input.face_tags.empty()) return invalid_input("tagged faces without a table of tags");
    if (!input.face_tags.empty()) {
      DTM_RETURN_IF_ERROR(check_region_table(input.face_tags).with_context("face tags"));
      if (input.face_tags.size() > kMaxFaceTags) return invalid_input("more face tags than a stream holds");
    }
    return Status::Ok();
  }();
  if (exchange.size() > 1) {
    // Every rank's verdict (one refusing alone would leave the others
    // waiting in their first exchange), then, with cell data, whether every
    // rank was given every tetrahedron: a cell's source may be any
    // tetrahedron around its corners, and the table's scales are every
    // tetrahedron's. Then the ranks own, together, as many as each holds.
    DTM_RETURN_IF_ERROR(agreed(exchange, checked));
    std::optional<ReferenceShare> made;
    const ReferenceShare& share =
        input.share ? *input.share
                    : made.emplace(input.points, input.grid.qbits, exchange.rank(), exchange.size());
    uint64_t owned = 0;
    for (const auto& t : input.reference_tets) owned += share.owns(t);
    // (Bit 0: cell data; bit 1: tagged faces. Either needs every
    // tetrahedron; the tagged faces, the same ones on every rank.)
    const uint8_t needs = static_cast<uint8_t>((input.cell_values ? 1 : 0) | (input.faces ? 2 : 0));
    const uint64_t faces = input.faces ? input.faces->fingerprint() : 0;
    ByteWriter w;
    w.u8(needs);
    w.u64(owned);
    w.u64(input.reference_tets.size());
    w.u64(faces);
    uint64_t all = 0;
    bool same_needs = true, same_faces = true;
    for (const auto& bytes : exchange.all_gather(w.take())) {
      BlockReader r(bytes);
      const uint8_t needs_there = r.u8();
      const uint64_t owned_there = r.u64(), given_there = r.u64(), faces_there = r.u64();
      all += owned_there;
      same_needs =
          same_needs && needs_there == needs && (!needs || given_there == input.reference_tets.size());
      same_faces = same_faces && faces_there == faces;
    }
    if (!same_needs || (needs && all != input.reference_tets.size())) {
      static constexpr const char* kWhat[] = {"cell data or tagged faces", "cell data", "tagged faces",
                                              "cell data and tagged faces"};
      const std::string what = kWhat[needs];
      return invalid_input(what + " on ranks need every input tetrahedron (and its values) on every rank");
    }
    if (!same_faces)
      return invalid_input("tagged faces on ranks need the same tagged triangles on every rank");
  } else {
    DTM_RETURN_IF_ERROR(checked);
  }
  BrickedEncoder encoder(input, options, exchange);
  return encoder.run(on_level);
}

}  // namespace dtm
