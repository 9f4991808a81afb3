#include "codec/blocks/rank_reference.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include "codec/blocks/reference_share.h"
#include "common/byte_io.h"
#include "common/release.h"
#include "mesh/topology.h"

namespace dtm {
namespace {

// The reference's extent over the ranks: each rank's, gathered and added.
ReferenceSolid::Extent whole_extent(RankExchange& x, const ReferenceSolid::Extent& mine) {
  ByteWriter w;
  w.u64(mine.tetrahedra);
  w.u8(mine.any ? 1 : 0);
  for (int a = 0; a < 3; ++a)
    w.u64(static_cast<uint64_t>(mine.lo[a])), w.u64(static_cast<uint64_t>(mine.hi[a]));
  ReferenceSolid::Extent whole;
  for (const auto& bytes : x.all_gather(w.take())) {
    BlockReader r(bytes);
    ReferenceSolid::Extent e;
    e.tetrahedra = r.u64();
    e.any = r.u8() != 0;
    for (int a = 0; a < 3; ++a)
      e.lo[a] = static_cast<int64_t>(r.u64()), e.hi[a] = static_cast<int64_t>(r.u64());
    whole.add(e);
  }
  return whole;
}

// Every rank's triangles, in rank order, on every rank.
std::vector<std::array<uint32_t, 3>> gather_all(RankExchange& x, std::vector<std::array<uint32_t, 3>> mine) {
  ByteWriter w;
  w.u64(mine.size());
  for (const auto& t : mine)
    for (uint32_t v : t) w.u32(v);
  release(mine);
  std::vector<std::vector<uint8_t>> parts = x.all_gather(w.take());
  size_t total = 0;
  for (const auto& bytes : parts) total += BlockReader(bytes).u64();
  std::vector<std::array<uint32_t, 3>> all;
  all.reserve(total);
  for (auto& bytes : parts) {
    BlockReader r(bytes);
    for (uint64_t i = r.u64(); i > 0; --i) {
      std::array<uint32_t, 3>& t = all.emplace_back();
      for (uint32_t& v : t) v = r.u32();
    }
    release(bytes);
  }
  return all;
}

}  // namespace

RankReference::RankReference(std::span<const GridPoint> points, int qbits, RankExchange& exchange,
                             const Solid* voxels, PhaseCallback on_phase)
    : points_(points), qbits_(qbits), x_(exchange), voxels_(voxels), on_phase_(std::move(on_phase)) {
  solid_ = voxels;
}

void RankReference::set_whole(std::span<const std::array<uint32_t, 4>> tets,
                              std::span<const uint8_t> regions) {
  report_phase(on_phase_, "the reference's boundary");
  std::vector<std::array<uint32_t, 3>> boundary =
      regions.empty() ? boundary_triangles(tets) : region_surface_triangles(tets, regions);
  report_phase(on_phase_, "the reference solid");
  if (regions.empty())
    tet_solid_.emplace(points_, tets, boundary);
  else
    region_solid_.emplace(points_, tets, regions);
  if (!voxels_) solid_ = region_solid_ ? static_cast<const Solid*>(&*region_solid_) : &*tet_solid_;
  faces_.emplace(points_, std::move(boundary), qbits_);
  whole_.reset();
}

void RankReference::set_in_parts(std::span<const std::array<uint32_t, 4>> given,
                                 std::span<const uint8_t> regions, size_t region_count,
                                 const ReferenceShare* share, const std::function<void()>& tets_done) {
  using Tet = std::array<uint32_t, 4>;
  std::optional<ReferenceShare> made;
  const ReferenceShare& s = share ? *share : made.emplace(points_, qbits_, x_.rank(), x_.size());
  // (The same on every rank, whatever it holds.)
  const bool by_region = region_count > 1;
  const size_t count = by_region ? region_count : 1;
  // What this rank holds of what it was given (all, when given its share),
  // and their regions.
  std::vector<Tet> kept;
  std::vector<uint8_t> kept_regions;
  std::span<const Tet> held = given;
  std::span<const uint8_t> held_regions = regions;
  const auto holds = [&](const Tet& t) { return s.holds(t); };
  if (!std::all_of(given.begin(), given.end(), holds)) {
    for (size_t i = 0; i < given.size(); ++i) {
      if (!holds(given[i])) continue;
      kept.push_back(given[i]);
      if (by_region) kept_regions.push_back(regions[i]);
    }
    held = kept, held_regions = kept_regions;
  }
  const auto owns = [&](const Tet& t) { return s.owns(t); };
  const std::function<bool(const Tet&)> held_here = holds, own = owns;
  // Per region (one without regions), as RegionSolid holds them: the
  // extent of all its cells, the faces of exactly one of them (each found
  // by the rank of its least corner, gathered and put in the order one
  // process finds them), and this rank's cells near them (no rank gathers
  // them all; the blocks ask the ranks what a part does not know).
  struct Region {
    ReferenceSolid::Extent whole;
    std::vector<std::array<uint32_t, 3>> boundary;
    std::vector<Tet> near;
  };
  std::vector<Region> parts(count);
  report_phase(on_phase_, "the reference's boundary");
  for (size_t r = 0; r < count; ++r) {
    std::vector<Tet> of_region;
    std::span<const Tet> cells = held;
    if (by_region) {
      for (size_t i = 0; i < held.size(); ++i)
        if (held_regions[i] == r + 1) of_region.push_back(held[i]);
      cells = of_region;
    }
    Region& part = parts[r];
    part.whole = whole_extent(
        x_, ReferenceSolid::Extent::of(
                points_, cells, static_cast<uint64_t>(std::count_if(cells.begin(), cells.end(), owns))));
    if (part.whole.tetrahedra == 0) continue;  // no rank has any
    part.boundary = boundary_triangles(cells);
    std::erase_if(part.boundary, [&](const std::array<uint32_t, 3>& t) {
      return !s.mine(std::min({t[0], t[1], t[2]}));
    });
    part.boundary = gather_all(x_, std::move(part.boundary));
    sort_as_boundary_triangles(part.boundary);
    part.near = ReferenceSolid::near_boundary(points_, cells, part.boundary, part.whole, held_here);
  }
  if (std::none_of(parts.begin(), parts.end(), [](const Region& p) { return p.whole.tetrahedra > 0; }))
    return;
  // The tetrahedra are read no more.
  release(kept);
  release(kept_regions);
  held = {}, held_regions = {};
  tets_done();
  report_phase(on_phase_, "the reference solid");
  std::vector<std::array<uint32_t, 3>> surface;
  ReferenceParts& made_parts = parts_.emplace();
  made_parts.regions.resize(count);
  for (size_t r = 0; r < count; ++r) {
    Region& part = parts[r];
    if (part.whole.tetrahedra == 0) continue;  // on every rank alike
    made_parts.regions[r].emplace(points_, part.near, own, part.boundary, part.whole, x_);
    release(part.near);
    if (surface.empty())
      surface = std::move(part.boundary);
    else
      surface.insert(surface.end(), part.boundary.begin(), part.boundary.end());
    release(part.boundary);
  }
  // With regions, the boundary holds the interfaces (each face once), as
  // region_surface_triangles() makes it.
  if (by_region) surface = merged_region_boundaries(std::move(surface));
  if (voxels_) {
    parts_.reset();  // the voxels are the solid
  } else {
    const ReferenceParts& asked = *parts_;
    answers_ = x_.answer_while_working(
        [&asked](std::span<const uint8_t> question) { return answer_questions(asked, question); });
  }
  faces_.emplace(points_, std::move(surface), qbits_);
  whole_.reset();
}

void RankReference::release_all() {
  answers_.reset();  // first: it reads the parts
  parts_.reset();
  tet_solid_.reset();
  region_solid_.reset();
  solid_ = voxels_;
  book_ = {};
  faces_.reset();
  std::lock_guard lock(whole_mutex_);
  whole_.reset();
}

std::optional<BlockReference> RankReference::for_region(const GridBox& region, const Solid* solid,
                                                        bool measured) const {
  if (!solid_ && !parts_) return std::nullopt;
  BlockReference r;
  r.solid = solid;
  if (!faces_ || !measured) return r;
  std::vector<std::array<uint32_t, 3>> meeting = faces_->meeting(region);
  if (meeting.size() < faces_->size()) {
    r.shape.emplace(ReferenceShape::from_boundary(points_, std::move(meeting)));
    return r;
  }
  // All of it, in the index's order: the boundary built before, if any
  // (the same triangles in the same order, so the same measurements).
  std::shared_ptr<const ReferenceBoundary> whole;
  {
    std::lock_guard lock(whole_mutex_);
    if (!whole_) whole_ = std::make_shared<const ReferenceBoundary>(points_, std::move(meeting), false);
    whole = whole_;
  }
  r.shape.emplace(std::move(whole));
  return r;
}

std::vector<std::vector<uint8_t>> RankReference::run_carving(
    const BlockPlan& plan, const std::function<StatusOr<std::vector<uint8_t>>(size_t, const Solid*)>& work,
    Status& status, int at_once) {
  if (!parts_)
    return run_blocks(
        plan, x_, [&](size_t k) { return work(k, solid_); }, status, at_once);
  return run_blocks_asking(
      plan, x_, *parts_, book_, answers_.get(),
      [&](size_t k, const Solid& asking) { return work(k, &asking); }, status, questions_, at_once);
}

}  // namespace dtm
