#include "codec/bricked_encoder.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "codec/block_levels.h"
#include "codec/block_runs.h"
#include "codec/bricks.h"
#include "codec/format.h"
#include "codec/reference_questions.h"
#include "codec/reference_share.h"
#include "common/byte_io.h"
#include "common/parallel_for.h"
#include "common/release.h"
#include "core/nearest_spacing.h"
#include "core/reference_solid.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

Status invalid(const std::string& what) { return {StatusCode::kInvalidInput, what}; }

// The halo of a block: three kept radii (block_levels.h).
constexpr double kHaloKeptRadii = 3.0;
// alpha of a bricked level (spec/HIERARCHY.md §6.5): this many times the
// mean distance from a vertex to its nearest neighbour.
constexpr double kAlphaPerSpacing = 1.5;
// A coarser level keeps no cell of circumradius above this many times the
// finer level's alpha (its kept_radius: about twice its own alpha, a level
// having about 2^(1/3) times the finer one's spacing); level 0, twice its own.
constexpr double kKeptRadiusPerFinerAlpha = 2.5;
constexpr double kKeptRadiusOfLevel0 = 2.0;
// As the whole-level builder (core/codec_hierarchy.cpp): a level removing
// less than this share of what is asked is not built, and a level that
// breaks a bound is tried once more removing less.
constexpr double kThinLevelShare = 0.3;
constexpr double kRetryShare = 0.6;

// What the encoder keeps of a level for the stream.
struct LevelOut {
  double alpha = 0, kept_radius = 0;
  int brick_depth = 0;
  std::map<uint64_t, std::vector<uint8_t>> carving;  // per brick
  uint64_t cell_hash = 0;
  LevelStats stats;
};

// Whether one octree node holds the other.
bool nested(uint64_t a, int depth_a, uint64_t b, int depth_b) {
  return depth_a <= depth_b ? (b >> (3 * (depth_b - depth_a))) == a : (a >> (3 * (depth_a - depth_b))) == b;
}

// The level's quality floor over each level-0 block: average_quality_floor
// times level 0's average there (a block of a coarser level takes the
// blocks of level 0 inside it, or around it).
struct QualityFloors {
  std::vector<uint64_t> blocks;
  std::vector<int> depth;
  std::vector<double> sum;
  std::vector<uint64_t> count;
  double factor = 0, whole = 0;

  double floor(uint64_t block, int depth_of_block) const {
    if (factor <= 0) return 0;
    double s = 0;
    uint64_t c = 0;
    for (size_t i = 0; i < blocks.size(); ++i)
      if (nested(blocks[i], depth[i], block, depth_of_block)) s += sum[i], c += count[i];
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
        index_(in.points, q_),
        level_of_(in.points.size(), 0) {
    solid_ = in.voxels;
    if (x_.size() > 1)
      set_reference_in_parts(in.reference_tets);
    else if (!in.reference_tets.empty())
      set_reference(in.reference_tets);
    tets_done();
  }

  StatusOr<BrickedEncoding> run(const std::function<void(const LevelStats&)>& on_level);

 private:
  void phase(int level, const std::string& what) const {
    report_phase(o_.hierarchy.on_phase, "level " + std::to_string(level) + ": " + what);
  }
  BlockRegion region_of(const BlockPlan& plan, size_t k, int level, int64_t halo) const;
  // The reference of a block's region, made once for the blocks of one
  // place: a box holding the region, its bounds rounded out to quarters of
  // the block (a block's region grows with the levels' halos, its
  // reference a few times only; at depth 0, the whole grid, once).
  // The reference from its tetrahedra (which must outlive the encoder).
  void set_reference(std::span<const std::array<uint32_t, 4>> tets);
  // The same on the ranks of a run, each holding at least its share of the
  // tetrahedra (codec/reference_share.h): each finds the boundary faces and
  // the tetrahedra near the boundary that are its own, and every rank gets
  // them all. The solid and the boundary are the same as one process makes.
  void set_reference_in_parts(std::span<const std::array<uint32_t, 4>> given);
  // Tells the caller, once, that the reference's tetrahedra are read no more.
  void tets_done() {
    if (in_.reference_tets_done && !tets_done_) in_.reference_tets_done();
    tets_done_ = true;
  }
  // The reference a block is carved to (`solid`: solid_, or what a block's
  // work asks of the ranks' parts) and measured against; none for level 0
  // when alpha carves it.
  std::optional<BlockReference> reference_for(const GridBox& region, const Solid* solid) const;
  // run_blocks() of work carving to the reference: with the reference in
  // parts, each block's work run again until the ranks answered all it asked.
  std::vector<std::vector<uint8_t>> run_carving(
      const BlockPlan& plan, const std::function<StatusOr<std::vector<uint8_t>>(size_t, const Solid*)>& work,
      Status& status);
  StatusOr<double> level_alpha(std::span<const uint32_t> ids, const BlockPlan& plan);
  Status analyse(int level, const BlockPlan& plan, int64_t halo, const BlockAnalysisOptions& options,
                 std::vector<BlockAnalysis>& out);
  // The coarser level from the choice: builds, repairs, and merges until no
  // block's region changes. Sets coarser_ (per grid point).
  Status build(int level, const BlockPlan& plan, int64_t halo, double kept_radius,
               const QualityFloors& floors, uint64_t& broken, bool& quality_met, int& rounds);
  StatusOr<std::vector<uint8_t>> base_carving(int level, const LevelOut& out);
  StatusOr<BrickedEncoding> write_stream(std::vector<LevelOut>& levels);

  const BrickedEncodeInput& in_;
  const BrickedEncodeOptions& o_;
  RankExchange& x_;
  int q_;
  MortonIndex index_;
  std::vector<uint8_t> level_of_;  // per grid point: the coarsest level that holds it
  // The reference: its solid (the input's tetrahedra, or level 0's carving,
  // or the scan's voxels), whole, or this rank's part on ranks, and its boundary triangles
  // by place (none before level 0 is built, when level 0 is the reference).
  std::vector<std::array<uint32_t, 4>> level0_cells_;  // until they are the solid
  std::optional<ReferenceSolid> tet_solid_;            // whole, or this rank's part
  const Solid* solid_ = nullptr;
  bool parts_ = false;  // solid_ is tet_solid_, a part
  AnswerBook book_;     // what the ranks answered of this level's questions
  QuestionCount questions_;
  std::optional<TriangleIndex> faces_;
  SurfaceRecord record_;  // the finer level's
  std::vector<std::pair<uint32_t, double>> reference_squared_;
  std::vector<uint8_t> coarser_;  // per grid point: in the level being built
  uint64_t reference_boundary_vertices_ = 0;
  bool tets_done_ = false;
};

BlockRegion BrickedEncoder::region_of(const BlockPlan& plan, size_t k, int level, int64_t halo) const {
  BlockRegion b;
  b.owned = plan.box(k, q_);
  b.region = b.owned.grown(halo, q_);
  b.ids = index_.inside(b.region, level_of_, level);
  b.points = gather(in_.points, b.ids);
  return b;
}

void BrickedEncoder::set_reference(std::span<const std::array<uint32_t, 4>> tets) {
  report_phase(o_.hierarchy.on_phase, "the reference's boundary");
  std::vector<std::array<uint32_t, 3>> boundary = boundary_triangles(tets);
  report_phase(o_.hierarchy.on_phase, "the reference solid");
  tet_solid_.emplace(in_.points, tets, boundary);
  if (!in_.voxels) solid_ = &*tet_solid_;
  faces_.emplace(in_.points, std::move(boundary), q_);
}

void BrickedEncoder::set_reference_in_parts(std::span<const std::array<uint32_t, 4>> given) {
  std::optional<ReferenceShare> made;
  const ReferenceShare& share = in_.share ? *in_.share : made.emplace(in_.points, q_, x_.rank(), x_.size());
  // What this rank holds of what it was given (all, when given its share).
  std::vector<std::array<uint32_t, 4>> kept;
  std::span<const std::array<uint32_t, 4>> held = given;
  const auto holds = [&](const std::array<uint32_t, 4>& t) { return share.holds(t); };
  if (!std::all_of(given.begin(), given.end(), holds)) {
    std::copy_if(given.begin(), given.end(), std::back_inserter(kept), holds);
    held = kept;
  }
  const auto owns = [&](const std::array<uint32_t, 4>& t) { return share.owns(t); };
  ReferenceSolid::Extent whole;
  {
    const auto mine = ReferenceSolid::Extent::of(
        in_.points, held, static_cast<uint64_t>(std::count_if(held.begin(), held.end(), owns)));
    ByteWriter w;
    w.u64(mine.tetrahedra);
    w.u8(mine.any ? 1 : 0);
    for (int a = 0; a < 3; ++a)
      w.u64(static_cast<uint64_t>(mine.lo[a])), w.u64(static_cast<uint64_t>(mine.hi[a]));
    for (const auto& bytes : x_.all_gather(w.take())) {
      BlockReader r(bytes);
      ReferenceSolid::Extent e;
      e.tetrahedra = r.u64();
      e.any = r.u8() != 0;
      for (int a = 0; a < 3; ++a)
        e.lo[a] = static_cast<int64_t>(r.u64()), e.hi[a] = static_cast<int64_t>(r.u64());
      whole.add(e);
    }
  }
  if (whole.tetrahedra == 0) return;  // no rank has any
  // The faces of exactly one tetrahedron whose least corner is this rank's,
  // gathered and put in the order one process finds them.
  report_phase(o_.hierarchy.on_phase, "the reference's boundary");
  const auto gather_all = [&]<size_t N>(std::vector<std::array<uint32_t, N>> mine) {
    ByteWriter w;
    w.u64(mine.size());
    for (const auto& t : mine)
      for (uint32_t v : t) w.u32(v);
    release(mine);
    std::vector<std::vector<uint8_t>> parts = x_.all_gather(w.take());
    size_t total = 0;
    for (const auto& bytes : parts) total += BlockReader(bytes).u64();
    std::vector<std::array<uint32_t, N>> all;
    all.reserve(total);
    for (auto& bytes : parts) {
      BlockReader r(bytes);
      for (uint64_t i = r.u64(); i > 0; --i) {
        std::array<uint32_t, N>& t = all.emplace_back();
        for (uint32_t& v : t) v = r.u32();
      }
      release(bytes);
    }
    return all;
  };
  std::vector<std::array<uint32_t, 3>> boundary = boundary_triangles(held);
  std::erase_if(boundary, [&](const std::array<uint32_t, 3>& t) {
    return !share.mine(std::min({t[0], t[1], t[2]}));
  });
  boundary = gather_all(std::move(boundary));
  sort_as_boundary_triangles(boundary);
  report_phase(o_.hierarchy.on_phase, "the reference solid");
  // This rank's part: the tetrahedra near the boundary that it holds (no
  // rank gathers them all; the blocks ask the ranks what a part does not know).
  const std::function<bool(const std::array<uint32_t, 4>&)> held_here = holds, own = owns;
  std::vector<std::array<uint32_t, 4>> near =
      ReferenceSolid::near_boundary(in_.points, held, boundary, whole, held_here);
  // The tetrahedra are read no more.
  release(kept);
  held = {};
  tets_done();
  tet_solid_.emplace(in_.points, near, own, boundary, whole, x_);
  release(near);
  if (!in_.voxels) solid_ = &*tet_solid_, parts_ = true;
  faces_.emplace(in_.points, std::move(boundary), q_);
}

std::optional<BlockReference> BrickedEncoder::reference_for(const GridBox& region, const Solid* solid) const {
  if (!solid_) return std::nullopt;
  return block_reference(in_.points, solid, faces_ ? &*faces_ : nullptr, region);
}

std::vector<std::vector<uint8_t>> BrickedEncoder::run_carving(
    const BlockPlan& plan, const std::function<StatusOr<std::vector<uint8_t>>(size_t, const Solid*)>& work,
    Status& status) {
  if (!parts_)
    return run_blocks(
        plan, x_, [&](size_t k) { return work(k, solid_); }, status);
  return run_blocks_asking(
      plan, x_, *tet_solid_, book_, [&](size_t k, const Solid& asking) { return work(k, &asking); }, status,
      questions_);
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
      status);
  DTM_RETURN_IF_ERROR(status);
  double total = 0;
  for (const auto& s : sums) total += BlockReader(s).f64();
  return kAlphaPerSpacing * total / static_cast<double>(ids.size());
}

Status BrickedEncoder::analyse(int level, const BlockPlan& plan, int64_t halo,
                               const BlockAnalysisOptions& options, std::vector<BlockAnalysis>& out) {
  Status status = Status::Ok();
  auto results = run_carving(
      plan,
      [&](size_t k, const Solid* solid) -> StatusOr<std::vector<uint8_t>> {
        const BlockRegion block = region_of(plan, k, level, halo);
        std::optional<BlockReference> reference = reference_for(block.region, solid);
        DTM_ASSIGN_OR_RETURN(BlockAnalysis a,
                             analyse_block(block, reference ? &*reference : nullptr, options));
        return serialize(a);
      },
      status);
  DTM_RETURN_IF_ERROR(status);
  out.clear();
  for (auto& r : results) {
    out.push_back(deserialize_analysis(r));
    release(r);
  }
  return Status::Ok();
}

Status BrickedEncoder::build(int level, const BlockPlan& plan, int64_t halo, double kept_radius,
                             const QualityFloors& floors, uint64_t& broken, bool& quality_met, int& rounds) {
  LevelBounds bounds;
  bounds.dmax = o_.hierarchy.dmax;
  bounds.kept_radius = kept_radius;
  // Per block: its last result (region size as left), broken places,
  // quality, rounds; the blocks still to build.
  std::vector<uint64_t> left(plan.blocks.size(), 0), block_broken(plan.blocks.size(), 0);
  std::vector<uint8_t> met(plan.blocks.size(), 1), to_build(plan.blocks.size(), 1);
  std::vector<int> block_rounds(plan.blocks.size(), 0);
  // What a block's checks see: its box grown by 2 kept radii and D_max.
  // A point put back farther away changes none of the cells it owns that
  // the level keeps (their circumspheres lie within 2 kept radii of the box),
  // so none of its surface triangles nor the quality of its cells, and it
  // makes no surface within D_max of a reference vertex of the box.
  const int64_t reach = static_cast<int64_t>(std::ceil(2 * kept_radius + o_.hierarchy.dmax)) + 1;
  const auto seen = [&](size_t k) { return plan.box(k, q_).grown(reach, q_); };
  for (int pass = 0;; ++pass) {
    phase(level + 1, pass == 0 ? "building the blocks" : "building again where a neighbour put points back");
    Status status = Status::Ok();
    const auto results = run_carving(
        plan,
        [&](size_t k, const Solid* solid) -> StatusOr<std::vector<uint8_t>> {
          ByteWriter w;
          if (!to_build[k]) {
            w.u8(0);
            return w.take();
          }
          const BlockRegion fine = region_of(plan, k, level, halo);
          std::vector<uint8_t> keep(fine.ids.size());
          for (size_t i = 0; i < keep.size(); ++i) keep[i] = coarser_[fine.ids[i]];
          std::optional<BlockReference> reference = reference_for(fine.region, solid);
          LevelBounds b = bounds;
          b.quality_floor = floors.floor(plan.blocks[k], plan.depth[k]);
          DTM_ASSIGN_OR_RETURN(BlockBuild built,
                               build_block(fine, keep, record_, reference_squared_, *reference, b));
          // What it put back (the rest was chosen already), and how much of
          // the coarser level its checks saw.
          std::vector<uint32_t> back;
          const GridBox checked = seen(k);
          uint64_t in_sight = 0;
          for (uint32_t id : built.vertices) {
            if (!coarser_[id]) back.push_back(id);
            in_sight += checked.contains(in_.points[id]);
          }
          w.u8(1);
          w.u64(in_sight);
          w.u64(built.broken);
          w.u8(built.quality_met ? 1 : 0);
          w.u32(static_cast<uint32_t>(built.rounds));
          put(w, std::span<const uint32_t>(back));
          return w.take();
        },
        status);
    DTM_RETURN_IF_ERROR(status);
    for (size_t k = 0; k < results.size(); ++k) {
      BlockReader r(results[k]);
      if (!r.u8()) continue;
      left[k] = r.u64();
      block_broken[k] = r.u64();
      met[k] = r.u8();
      block_rounds[k] = std::max(block_rounds[k], static_cast<int>(r.u32()));
      for (uint32_t id : r.u32s()) coarser_[id] = 1;
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
            for (uint32_t id : index_.inside(seen(k), level_of_, level)) now += coarser_[id];
            return std::vector<uint8_t>{static_cast<uint8_t>(now > left[k] ? 1 : 0)};
          },
          s2);
      DTM_RETURN_IF_ERROR(s2);
      for (size_t k = 0; k < changed.size(); ++k) next[k] = changed[k].at(0), again = again || next[k];
    }
    if (!again || pass >= 6) {
      broken = 0;
      quality_met = true;
      rounds = 0;
      for (size_t k = 0; k < plan.blocks.size(); ++k) {
        broken += block_broken[k] + (next[k] ? 1 : 0);  // a block left unchecked counts as broken
        quality_met = quality_met && met[k];
        rounds = std::max(rounds, block_rounds[k]);
      }
      return Status::Ok();
    }
    to_build = next;
  }
}

StatusOr<std::vector<uint8_t>> BrickedEncoder::base_carving(int level, const LevelOut& out) {
  // The base layer is one chunk of depth 0 (§3.5): its carving over the
  // whole coarsest level, on rank 0, sent to every rank.
  BlockPlan one;
  one.blocks = {0};
  one.depth = {0};
  one.first = {0, 0};
  one.rank = {0};
  BlockAnalysisOptions options;
  options.qbits = q_;
  options.alpha = out.alpha;
  options.kept_radius = out.kept_radius;
  options.brick_depth = 0;
  std::vector<BlockAnalysis> a;
  DTM_RETURN_IF_ERROR(analyse(level, one, 0, options, a));
  if (a.at(0).carving.empty()) return std::vector<uint8_t>{};
  return std::move(a[0].carving[0].second);
}

StatusOr<BrickedEncoding> BrickedEncoder::run(const std::function<void(const LevelStats&)>& on_level) {
  const HierarchyOptions& h = o_.hierarchy;
  const int ranks = x_.size();
  std::vector<MortonCode> codes;
  std::vector<uint32_t> ids;
  index_.level(level_of_, 0, codes, &ids);
  const int finest_depth = choose_brick_depth(codes, q_, 2 * o_.brick_points);
  const double share = h.removal_share > 0 ? h.removal_share : 0.5;
  QualityFloors floors;
  floors.factor = h.average_quality_floor;
  std::vector<LevelOut> levels;
  // The coarser level's figures made while building it, for its row, and
  // the largest circumradius it keeps.
  LevelStats built_stats;
  double next_kept_radius = 0;
  bool last = false;
  for (int level = 0;; ++level) {
    if (level > 250) return invalid("more than 250 levels");
    book_ = {};  // a level's questions are of its own cells
    index_.level(level_of_, level, codes, &ids);
    LevelOut out;
    out.brick_depth =
        std::min(finest_depth, choose_brick_depth(codes, q_, std::max<uint64_t>(1, o_.brick_points / 4)));
    const BlockPlan plan = plan_blocks(codes, q_, out.brick_depth, o_.block_points, ranks);
    release(codes);  // 16 bytes a point, not held while the blocks are built
    size_t largest = 0;
    for (size_t k = 0; k < plan.blocks.size(); ++k)
      largest = std::max(largest, plan.first[k + 1] - plan.first[k]);
    phase(level, "alpha");
    DTM_ASSIGN_OR_RETURN(out.alpha, level_alpha(ids, plan));
    if (!(out.alpha > 0)) return invalid("the level's points do not span three dimensions");
    // kept_radius is the build's, alpha (a prediction) at most that (§3.5).
    out.kept_radius = level == 0 ? kKeptRadiusOfLevel0 * out.alpha : next_kept_radius;
    out.alpha = std::min(out.alpha, out.kept_radius);
    const double kept_radius = out.kept_radius;
    next_kept_radius = kKeptRadiusPerFinerAlpha * out.alpha;
    const int64_t halo =
        static_cast<int64_t>(std::ceil(kHaloKeptRadii * std::max(kept_radius, next_kept_radius))) + 1;
    const bool may_choose = !last && !(h.max_levels > 0 && level >= h.max_levels);

    BlockAnalysisOptions options;
    options.qbits = q_;
    options.alpha = out.alpha;
    options.kept_radius = kept_radius;
    options.brick_depth = out.brick_depth;
    options.collect_cells = level == 0 && !faces_;
    if (may_choose) options.choice = CoarseningOptions{1 - share, h.dmax, 0.85};
    phase(level, "Delaunay tetrahedralization, carving and choice in " + std::to_string(plan.blocks.size()) +
                     " blocks of at most " + std::to_string(largest) + " points");
    std::vector<BlockAnalysis> analysis;
    DTM_RETURN_IF_ERROR(analyse(level, plan, halo, options, analysis));

    // The level's figures, carving and surface record, merged in block order.
    LevelStats& s = out.stats;
    s = built_stats;
    s.level = level;
    s.vertices = ids.size();
    s.alpha = out.alpha;
    DistanceSums to_level, to_reference;
    double quality_sum = 0, quality_min = INFINITY;
    record_ = {};
    reference_squared_.clear();
    std::vector<uint32_t> boundary;
    {
      size_t triangles = 0, vertices = 0, squared = 0, owned_boundary = 0;
      for (const BlockAnalysis& a : analysis) {
        triangles += a.surface_triangles.size(), vertices += a.surface_vertices.size();
        squared += a.reference_squared.size(), owned_boundary += a.boundary.size();
      }
      record_.triangles.reserve(triangles);
      record_.vertices.reserve(vertices);
      reference_squared_.reserve(squared);
      boundary.reserve(owned_boundary);
    }
    // Each block's parts freed once merged: only its choice is read later
    // (and its figures, which are small).
    for (BlockAnalysis& a : analysis) {
      const BlockFigures& f = a.figures;
      s.boundary_vertices += f.boundary_vertices;
      s.tetrahedra += f.cells;
      quality_sum += f.quality_sum;
      quality_min = std::min(quality_min, f.quality_min);
      to_level.add(f.to_level);
      to_reference.add(f.to_reference);
      out.cell_hash += f.cell_hash;
      for (auto& [brick, bytes] : a.carving) out.carving[brick] = std::move(bytes);
      record_.triangles.insert(record_.triangles.end(), a.surface_triangles.begin(),
                               a.surface_triangles.end());
      record_.vertices.insert(record_.vertices.end(), a.surface_vertices.begin(), a.surface_vertices.end());
      reference_squared_.insert(reference_squared_.end(), a.reference_squared.begin(),
                                a.reference_squared.end());
      boundary.insert(boundary.end(), a.boundary.begin(), a.boundary.end());
      if (level == 0 && !faces_) level0_cells_.insert(level0_cells_.end(), a.carved.begin(), a.carved.end());
      BlockAnalysis kept;
      kept.figures = a.figures;
      kept.chosen = std::move(a.chosen);
      a = std::move(kept);
    }
    std::sort(record_.triangles.begin(), record_.triangles.end());
    std::sort(record_.vertices.begin(), record_.vertices.end());
    std::sort(reference_squared_.begin(), reference_squared_.end());
    std::sort(boundary.begin(), boundary.end());
    s.avg_min_solid_angle = s.tetrahedra ? quality_sum / static_cast<double>(s.tetrahedra) : 0;
    s.min_solid_angle = s.tetrahedra ? quality_min : 0;
    if (to_level.count + to_reference.count > 0) {
      ShapeFigures shape;
      shape.to_level = {to_level.max, to_level.count ? to_level.sum / to_level.count : 0};
      shape.to_reference = {to_reference.max, to_reference.count ? to_reference.sum / to_reference.count : 0};
      shape.both = {
          std::max(to_level.max, to_reference.max),
          (to_level.sum + to_reference.sum) / static_cast<double>(to_level.count + to_reference.count)};
      s.reference_shape = shape;
      reference_boundary_vertices_ = to_level.count;
      s.max_boundary_error = shape.to_level.max;
      s.mean_boundary_error = shape.to_level.mean;
    } else if (level == 0) {
      s.reference_shape = ShapeFigures{};  // level 0 is its own reference
    }
    if (level == 0) {
      floors.blocks = plan.blocks;
      floors.depth = plan.depth;
      for (const BlockAnalysis& a : analysis) {
        floors.sum.push_back(a.figures.quality_sum);
        floors.count.push_back(a.figures.cells);
      }
      floors.whole = s.avg_min_solid_angle;
      if (!faces_) {
        // Level 0's carving is the reference from now on (the solid, unless
        // the voxels are), and its surface the reference's: every distance
        // to it is 0.
        std::sort(level0_cells_.begin(), level0_cells_.end());
        set_reference(level0_cells_);
        release(level0_cells_);
        reference_squared_.clear();
      }
    }
    if (on_level) on_level(s);
    levels.push_back(std::move(out));
    if (!may_choose) break;

    // The coarser level: chosen, built and repaired; once more removing
    // less where that fails; else this level is the coarsest.
    const size_t finer = ids.size();
    bool accepted = false;
    for (const double attempt : {share, kRetryShare * share}) {
      coarser_.assign(in_.points.size(), 0);
      if (attempt == share) {
        for (const BlockAnalysis& a : analysis)
          for (uint32_t id : a.chosen) coarser_[id] = 1;
      } else {
        phase(level + 1, "choosing again, fewer");
        options.choice = CoarseningOptions{1 - attempt, h.dmax, 0.85};
        options.brick_depth = -1;
        options.collect_cells = false;
        std::vector<BlockAnalysis> again;
        DTM_RETURN_IF_ERROR(analyse(level, plan, halo, options, again));
        for (const BlockAnalysis& a : again)
          for (uint32_t id : a.chosen) coarser_[id] = 1;
      }
      uint64_t chosen = 0;
      for (uint32_t id : ids) chosen += coarser_[id];
      uint64_t broken = 0;
      bool quality_met = true;
      int rounds = 0;
      DTM_RETURN_IF_ERROR(build(level, plan, halo, next_kept_radius, floors, broken, quality_met, rounds));
      uint64_t coarser = 0, removed_boundary = 0;
      for (uint32_t id : ids) coarser += coarser_[id];
      for (uint32_t id : boundary) removed_boundary += !coarser_[id];
      if (coarser < h.min_base_vertices) break;
      if (static_cast<double>(finer - coarser) < kThinLevelShare * share * static_cast<double>(finer) ||
          !quality_met || broken > 0)
        continue;
      accepted = true;
      built_stats = {};
      built_stats.removed_boundary = removed_boundary;
      built_stats.removed_interior = finer - coarser - removed_boundary;
      built_stats.passes = 1;
      built_stats.chosen = chosen;
      built_stats.put_back = coarser - chosen;
      built_stats.repair_rounds = rounds;
      last = h.stop_when_boundary_is_final && removed_boundary == 0;
      break;
    }
    if (!accepted) break;
    for (uint32_t id : ids)
      if (coarser_[id]) level_of_[id] = static_cast<uint8_t>(level + 1);
  }
  release(coarser_);
  return write_stream(levels);
}

StatusOr<BrickedEncoding> BrickedEncoder::write_stream(std::vector<LevelOut>& levels) {
  const int coarsest = static_cast<int>(levels.size()) - 1;
  // The base layer is one chunk of depth 0.
  if (levels[coarsest].brick_depth != 0 || levels[coarsest].carving.size() > 1) {
    report_phase(o_.hierarchy.on_phase, "the base layer's carving");
    DTM_ASSIGN_OR_RETURN(std::vector<uint8_t> base, base_carving(coarsest, levels[coarsest]));
    levels[coarsest].carving.clear();
    if (!base.empty()) levels[coarsest].carving[0] = std::move(base);
  }
  levels[coarsest].brick_depth = 0;

  StreamHeader header;
  header.grid = in_.grid;
  header.alpha_policy = o_.hierarchy.alpha.kind;
  header.version_major = kVersionMajor;
  header.flags = static_cast<uint16_t>((o_.cell_hashes ? kFlagCellHashes : 0) | kFlagCarvingCorrections |
                                       kFlagBricks | (in_.values ? kFlagValues : 0));
  header.level_count = static_cast<uint16_t>(levels.size());
  header.vertex_count = static_cast<uint32_t>(in_.points.size());
  BrickedEncoding out;
  out.reference_boundary_vertices = reference_boundary_vertices_;
  out.reference_questions = questions_.questions;
  out.reference_question_runs = questions_.runs;
  out.bytes = write_header(header);
  if (in_.values) {
    const std::vector<uint8_t> table = write_field_table(in_.values->descriptions());
    out.field_table_bytes = table.size();
    out.bytes.insert(out.bytes.end(), table.begin(), table.end());
  }
  const size_t L = levels.size();
  out.value_bytes.assign(L, 0);
  out.level_field_bytes.assign(L, {});
  out.layer_bytes.assign(L, 0);
  out.carving_bytes.assign(L, 0);
  out.chunk_count.assign(L, 0);
  out.index_bytes.assign(L, 0);
  out.brick_depth.assign(L, 0);
  for (const LevelOut& l : levels) out.levels.push_back(l.stats);

  SetCoderModels models;
  models.enable_coordinate_reuse(q_);
  std::vector<MortonCode> known;  // V_{l+1}, ascending
  out.decode_order.reserve(in_.points.size());
  for (int level = coarsest; level >= 0; --level) {
    report_phase(o_.hierarchy.on_phase, "writing level " + std::to_string(level) + "'s layer");
    LevelOut& lo = levels[static_cast<size_t>(level)];
    const int depth = lo.brick_depth;
    // The layer's points in Morton order (their codes are not kept: at
    // level 0 they were the largest thing every rank held).
    const std::vector<uint32_t> ids = index_.level_ids(level_of_, level);
    std::vector<GridPoint> fresh;
    for (uint32_t id : ids)
      if (level_of_[id] == level) {
        fresh.push_back(in_.points[id]);
        out.decode_order.push_back(id);
      }
    // The bricks with points; their payloads, made by the ranks in turn.
    std::vector<uint64_t> bricks;
    std::vector<size_t> first;
    for (size_t i = 0; i < fresh.size(); ++i) {
      const uint64_t b = brick_of(morton_encode(fresh[i], q_), q_, depth);
      if (bricks.empty() || bricks.back() != b) bricks.push_back(b), first.push_back(i);
    }
    first.push_back(fresh.size());
    BlockPlan plan;  // the bricks, shared out among the ranks
    plan.blocks = bricks;
    plan.depth.assign(bricks.size(), depth);
    plan.first = first;
    assign_ranks(plan, x_.size());
    std::vector<std::vector<uint8_t>> payloads(bricks.size());
    if (known.empty()) {
      payloads.at(0) = encode_point_set({}, fresh, q_, models, brick_node(0, q_, 0));
    } else {
      Status status = Status::Ok();
      payloads = run_blocks(
          plan, x_,
          [&](size_t k) -> StatusOr<std::vector<uint8_t>> {
            const std::span<const GridPoint> points(fresh.data() + first[k], first[k + 1] - first[k]);
            const std::span<const MortonCode> inside = known_in_brick(known, bricks[k], q_, depth);
            SetCoderModels chunk = chunk_models(models, inside, q_);
            return encode_point_set(inside, points, q_, chunk, brick_node(bricks[k], q_, depth));
          },
          status);
      DTM_RETURN_IF_ERROR(status);
    }
    // Their values, each chunk's from the coarser levels' in its brick.
    std::vector<std::vector<uint8_t>> values(bricks.size());
    if (in_.values) {
      std::vector<uint32_t> coarser_ids;  // V_{l+1} in Morton order, as `known`
      std::vector<GridPoint> coarser_points;
      for (uint32_t id : ids)
        if (level_of_[id] > level) coarser_ids.push_back(id), coarser_points.push_back(in_.points[id]);
      std::vector<uint32_t> fresh_ids;
      for (uint32_t id : ids)
        if (level_of_[id] == level) fresh_ids.push_back(id);
      Status status = Status::Ok();
      const auto coded = run_blocks(
          plan, x_,
          [&](size_t k) -> StatusOr<std::vector<uint8_t>> {
            const int shift = 3 * (q_ - depth);
            const auto lo = std::lower_bound(known.begin(), known.end(), MortonCode{bricks[k]} << shift);
            const auto hi = std::lower_bound(known.begin(), known.end(), MortonCode{bricks[k] + 1} << shift);
            const size_t a = static_cast<size_t>(lo - known.begin()),
                         b = static_cast<size_t>(hi - known.begin());
            std::vector<uint64_t> field_bytes;
            const std::vector<uint8_t> section = in_.values->encode_chunk(
                std::span(coarser_ids).subspan(a, b - a), std::span(coarser_points).subspan(a, b - a),
                std::span(fresh_ids).subspan(first[k], first[k + 1] - first[k]),
                std::span(fresh).subspan(first[k], first[k + 1] - first[k]), field_bytes);
            ByteWriter w;
            put(w, std::span<const uint8_t>(section));
            w.u64(field_bytes.size());
            for (uint64_t f : field_bytes) w.u64(f);
            return w.take();
          },
          status);
      DTM_RETURN_IF_ERROR(status);
      out.level_field_bytes[static_cast<size_t>(level)].assign(in_.values->descriptions().size(), 0);
      for (size_t k = 0; k < bricks.size(); ++k) {
        BlockReader r(coded[k]);
        values[k] = r.bytes();
        const uint64_t fields = r.u64();
        for (uint64_t f = 0; f < fields; ++f) out.level_field_bytes[static_cast<size_t>(level)][f] += r.u64();
      }
    }
    // The chunks: every brick with points or corrections, ascending.
    std::vector<BrickChunk> chunks;
    std::vector<uint8_t> chunk_bytes;
    auto carving = lo.carving.begin();
    size_t p = 0;
    while (p < bricks.size() || carving != lo.carving.end()) {
      const uint64_t brick = std::min(p < bricks.size() ? bricks[p] : UINT64_MAX,
                                      carving != lo.carving.end() ? carving->first : UINT64_MAX);
      BrickChunk chunk;
      chunk.brick = brick;
      const size_t start = chunk_bytes.size();
      if (p < bricks.size() && bricks[p] == brick) {
        chunk.new_points = static_cast<uint32_t>(first[p + 1] - first[p]);
        chunk.payload_bytes = static_cast<uint32_t>(payloads[p].size());
        chunk_bytes.insert(chunk_bytes.end(), payloads[p].begin(), payloads[p].end());
      }
      if (carving != lo.carving.end() && carving->first == brick) {
        chunk.carving_bytes = static_cast<uint32_t>(carving->second.size());
        chunk_bytes.insert(chunk_bytes.end(), carving->second.begin(), carving->second.end());
        out.carving_bytes[static_cast<size_t>(level)] += carving->second.size();
        ++carving;
      }
      if (p < bricks.size() && bricks[p] == brick) {
        chunk.value_bytes = static_cast<uint32_t>(values[p].size());
        chunk_bytes.insert(chunk_bytes.end(), values[p].begin(), values[p].end());
        out.value_bytes[static_cast<size_t>(level)] += values[p].size();
        ++p;
      }
      if (chunk.size() == 0) continue;
      chunk.checksum = chunk_checksum(std::span(chunk_bytes).subspan(start));
      chunks.push_back(chunk);
    }
    const std::vector<uint8_t> index = write_brick_index(chunks);
    LayerHeader lh;
    lh.format_major = kVersionMajor;
    lh.bricked = true;
    lh.level = static_cast<uint16_t>(level);
    lh.new_vertices = static_cast<uint32_t>(fresh.size());
    lh.level_vertices = static_cast<uint32_t>(ids.size());
    lh.alpha = lo.alpha;
    lh.kept_radius = lo.kept_radius;
    lh.brick_depth = static_cast<uint8_t>(depth);
    if (o_.cell_hashes) lh.cell_hash = lo.cell_hash;
    const std::vector<uint8_t> layer = write_bricked_layer(lh, index, chunk_bytes);
    out.layer_bytes[static_cast<size_t>(level)] = layer.size();
    out.chunk_count[static_cast<size_t>(level)] = chunks.size();
    out.index_bytes[static_cast<size_t>(level)] = index.size();
    out.brick_depth[static_cast<size_t>(level)] = depth;
    out.bytes.insert(out.bytes.end(), layer.begin(), layer.end());
    if (level > 0) merge_known(known, fresh, q_);  // V_l, for the finer layer
  }
  return out;
}

}  // namespace

int choose_brick_depth(std::span<const MortonCode> codes, int qbits, uint64_t target) {
  int best = 0;
  for (int depth = 1; depth <= std::min(qbits, kMaxBrickDepth); ++depth) {
    uint64_t bricks = 0, previous = UINT64_MAX;
    for (const MortonCode c : codes) {
      const uint64_t b = brick_of(c, qbits, depth);
      bricks += b != previous;
      previous = b;
    }
    if (bricks == 0 || codes.size() < target * bricks) break;
    best = depth;
  }
  return best;
}

StatusOr<BrickedEncoding> encode_bricked(const BrickedEncodeInput& input, const BrickedEncodeOptions& options,
                                         const std::function<void(const LevelStats&)>& on_level) {
  if (input.points.size() < 4) return invalid("fewer than four points make no tetrahedron");
  if (input.points.size() > (size_t{1} << 31)) return invalid("bricked streams hold at most 2^31 points");
  if (options.brick_points == 0 || options.block_points == 0)
    return invalid("brick and block points must be positive");
  if (options.hierarchy.alpha.kind == AlphaKind::kConvexHull)
    return invalid("bricked layers need a finite alpha (the halo of a region is a multiple of it)");
  if (options.hierarchy.alpha.kind == AlphaKind::kFixed && !(options.hierarchy.alpha.fixed_value > 0))
    return invalid("a fixed alpha must be positive");
  SingleProcess alone;
  RankExchange& exchange = options.exchange ? *options.exchange : alone;
  BrickedEncoder encoder(input, options, exchange);
  return encoder.run(on_level);
}

}  // namespace dtm
