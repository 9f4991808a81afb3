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

void RankReference::set_in_parts(std::span<const std::array<uint32_t, 4>> given, const ReferenceShare* share,
                                 const std::function<void()>& tets_done) {
  std::optional<ReferenceShare> made;
  const ReferenceShare& s = share ? *share : made.emplace(points_, qbits_, x_.rank(), x_.size());
  // What this rank holds of what it was given (all, when given its share).
  std::vector<std::array<uint32_t, 4>> kept;
  std::span<const std::array<uint32_t, 4>> held = given;
  const auto holds = [&](const std::array<uint32_t, 4>& t) { return s.holds(t); };
  if (!std::all_of(given.begin(), given.end(), holds)) {
    std::copy_if(given.begin(), given.end(), std::back_inserter(kept), holds);
    held = kept;
  }
  const auto owns = [&](const std::array<uint32_t, 4>& t) { return s.owns(t); };
  const ReferenceSolid::Extent whole = whole_extent(
      x_, ReferenceSolid::Extent::of(points_, held,
                                     static_cast<uint64_t>(std::count_if(held.begin(), held.end(), owns))));
  if (whole.tetrahedra == 0) return;  // no rank has any
  // The faces of exactly one tetrahedron whose least corner is this rank's,
  // gathered and put in the order one process finds them.
  report_phase(on_phase_, "the reference's boundary");
  std::vector<std::array<uint32_t, 3>> boundary = boundary_triangles(held);
  std::erase_if(boundary, [&](const std::array<uint32_t, 3>& t) {
    return !s.mine(std::min({t[0], t[1], t[2]}));
  });
  boundary = gather_all(x_, std::move(boundary));
  sort_as_boundary_triangles(boundary);
  report_phase(on_phase_, "the reference solid");
  // This rank's part: the tetrahedra near the boundary that it holds (no
  // rank gathers them all; the blocks ask the ranks what a part does not know).
  const std::function<bool(const std::array<uint32_t, 4>&)> held_here = holds, own = owns;
  std::vector<std::array<uint32_t, 4>> near =
      ReferenceSolid::near_boundary(points_, held, boundary, whole, held_here);
  // The tetrahedra are read no more.
  release(kept);
  held = {};
  tets_done();
  tet_solid_.emplace(points_, near, own, boundary, whole, x_);
  release(near);
  if (!voxels_) {
    solid_ = &*tet_solid_, parts_ = true;
    const ReferenceSolid& part = *tet_solid_;
    answers_ = x_.answer_while_working(
        [&part](std::span<const uint8_t> question) { return answer_questions(part, question); });
  }
  faces_.emplace(points_, std::move(boundary), qbits_);
  whole_.reset();
}

void RankReference::release_all() {
  answers_.reset();  // first: it reads the part
  tet_solid_.reset();
  region_solid_.reset();
  solid_ = voxels_;
  parts_ = false;
  book_ = {};
  faces_.reset();
  std::lock_guard lock(whole_mutex_);
  whole_.reset();
}

std::optional<BlockReference> RankReference::for_region(const GridBox& region, const Solid* solid) const {
  if (!solid_) return std::nullopt;
  BlockReference r;
  r.solid = solid;
  if (!faces_) return r;
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
      plan, x_, *tet_solid_, book_, answers_.get(),
      [&](size_t k, const Solid& asking) { return work(k, &asking); }, status, questions_, at_once);
}

}  // namespace dtm
