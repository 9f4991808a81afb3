// The exact cell coder's encoder (spec/FORMAT.md §3.10); exact_cell_decoder.cpp
// mirrors it, exact_cell_coder_shared.h holds the fill both make.
#include <algorithm>
#include <string>

#include "codec/sections/exact_cell_coder.h"
#include "codec/sections/exact_cell_coder_shared.h"

namespace dtm {
namespace exact_cells {
namespace {

// The symbols from the input: which of its cells lies across each open face.
class Encoder {
 public:
  Encoder(std::span<const MeshCell> rest, std::span<const GridPoint> points, ExactStats& stats)
      : rest_(rest), points_(points), placed_(rest.size(), 0), stats_(stats) {}

  // The faces of the cells to place (a face of three is not a mesh's).
  Status index() {
    across_.reserve(rest_.size() * 4);
    for (uint32_t i = 0; i < rest_.size(); ++i)
      for (int k = 0; k < 4; ++k) {
        const MeshCell& c = rest_[i];
        const FaceKey key = key_of({c[static_cast<size_t>((k + 1) % 4)], c[static_cast<size_t>((k + 2) % 4)],
                                    c[static_cast<size_t>((k + 3) % 4)]});
        auto [it, fresh] = across_.emplace(key, std::array<uint32_t, 2>{i, kNone});
        if (fresh) continue;
        if (it->second[1] != kNone)
          return invalid_input("three input cells share the face of corners " + std::to_string(key[0]) +
                               ", " + std::to_string(key[1]) + ", " + std::to_string(key[2]));
        it->second[1] = i;
      }
    return Status::Ok();
  }

  Status check() { return Status::Ok(); }

  bool filled(AdaptiveBit& model, const OpenFace& f) {
    ++stats_.open_faces;
    pending_ = kNone;
    const auto it = across_.find(key_of(f.outward));
    if (it != across_.end())
      for (uint32_t i : it->second)
        if (i != kNone && !placed_[i]) pending_ = i;
    rc_.encode(model, pending_ != kNone);
    return pending_ != kNone;
  }

  template <class Fit, class Ring>
  Status apex(const OpenFace& f, std::vector<uint32_t>& candidates, const ApexOrder& less, RankModels& models,
              const Fit& fit, const Ring& ring, uint32_t& apex) {
    const MeshCell& c = rest_[pending_];
    apex = apex_of(c, f);
    const bool candidate = std::find(candidates.begin(), candidates.end(), apex) != candidates.end();
    // The candidates ranked before the apex (all of them when it is not
    // one) and, in 12.0, of those only the ones that fit: the decoder tests
    // the same ones, and the apex.
    uint64_t rank = 0;
    for (uint32_t q : candidates) {
      if (candidate && !less(q, apex)) continue;
      bool fits = true;
      if (fit.on()) DTM_RETURN_IF_ERROR(fit(q, fits));
      rank += fits;
    }
    if (candidate && fit.on()) {
      bool fits = false;
      DTM_RETURN_IF_ERROR(fit(apex, fits));
      if (!fits) return invalid_input("input cell " + describe(c) + " overlaps another input cell");
    }
    put_rank(rc_, models, rank);
    if (!candidate)
      DTM_RETURN_IF_ERROR(escape(ring, less, apex));
    else if (rank == 0)
      ++stats_.rank_zero;
    place(pending_);
    return Status::Ok();
  }

  // 23.0: the apex's rank among the candidates that fit, in the search's
  // order; all of them when it is not one.
  template <class Search, class Ring>
  Status ranked_apex(const OpenFace& f, Search& search, const Ring& ring, uint32_t& apex) {
    const MeshCell& c = rest_[pending_];
    apex = apex_of(c, f);
    uint32_t q = 0;
    bool found = false;
    DTM_RETURN_IF_ERROR(search.next(q, found));
    RankModels& models = search.models();
    uint64_t rank = 0;
    while (found && q != apex) {
      ++rank;
      DTM_RETURN_IF_ERROR(search.next(q, found));
    }
    // (A candidate the search passed over overlaps a cell placed before
    // it, or crosses a face declared the boundary, as no input cell can.)
    if (!found && search.holds(apex))
      return invalid_input("input cell " + describe(c) +
                           " overlaps another input cell or gives a face a third cell");
    put_rank(rc_, models, rank);
    if (!found)
      DTM_RETURN_IF_ERROR(escape(ring, search.less(), apex));
    else if (rank == 0)
      ++stats_.rank_zero;
    place(pending_);
    return Status::Ok();
  }

  // 14.0: a flip is the input's when both its cells are input cells not
  // placed yet (the carving kept the three it replaces:
  // keep_flipped_cells()).
  bool flipped(AdaptiveBit& model, const FlipCandidate& f) {
    ++stats_.flip_candidates;
    const uint32_t a = unplaced(f.ring, f.edge[0]), b = unplaced(f.ring, f.edge[1]);
    const bool flip = a != kNone && b != kNone;
    rc_.encode(model, flip);
    if (!flip) return false;
    ++stats_.flips;
    for (uint32_t i : {a, b}) place(i);
    return true;
  }

  bool another_seed(AdaptiveBit& model) {
    while (next_seed_ < rest_.size() && placed_[next_seed_]) ++next_seed_;
    const bool more = next_seed_ < rest_.size();
    rc_.encode(model, more);
    return more;
  }

  Status seed(MeshCell& cell) {
    MeshCell c = rest_[next_seed_];
    std::sort(c.begin(), c.end());
    const int o = orientation(points_[c[0]], points_[c[1]], points_[c[2]], points_[c[3]]);
    if (o == 0) return invalid_input("input cell " + describe(c) + " is flat on the grid");
    if (o < 0) std::swap(c[2], c[3]);
    for (uint32_t v : c) rc_.encode_index(v, points_.size());
    cell = c;
    place(static_cast<uint32_t>(next_seed_));
    ++stats_.seeds;
    return Status::Ok();
  }

  void added(const MeshCell&) { ++stats_.fill_cells; }

  std::vector<uint8_t> finish() { return rc_.finish(); }
  // The input cell not placed yet of the face and the corner, or kNone.
  uint32_t unplaced(const std::array<uint32_t, 3>& face, uint32_t corner) const {
    const auto it = across_.find(key_of(face));
    if (it == across_.end()) return kNone;
    for (uint32_t i : it->second)
      if (i != kNone && !placed_[i] && std::find(rest_[i].begin(), rest_[i].end(), corner) != rest_[i].end())
        return i;
    return kNone;
  }
  std::vector<uint32_t>& source() { return source_; }

  // The corner of c off the face.
  static uint32_t apex_of(const MeshCell& c, const OpenFace& f) {
    uint32_t apex = c[0];
    for (uint32_t v : c)
      if (v != f.outward[0] && v != f.outward[1] && v != f.outward[2]) apex = v;
    return apex;
  }
  void place(uint32_t i) {
    source_.push_back(i);
    placed_[i] = 1;
  }
  // An apex that is not a candidate (or, in 23.0, not one that fits): in
  // 13.0 and later its rank in the second ring, one past it for an index.
  template <class Ring>
  Status escape(const Ring& ring, const ApexOrder& less, uint32_t apex) {
    ++stats_.escapes;
    bool in_ring = false;
    if (ring.on()) {
      DTM_RETURN_IF_ERROR(ring(second_));
      in_ring = std::find(second_.begin(), second_.end(), apex) != second_.end();
      const uint64_t second_rank =
          in_ring ? static_cast<uint64_t>(std::count_if(second_.begin(), second_.end(),
                                                        [&](uint32_t q) { return less(q, apex); }))
                  : second_.size();
      put_rank(rc_, ring.models(), second_rank);
      stats_.second_ring += in_ring;
    }
    if (!in_ring) rc_.encode_index(apex, points_.size());
    return Status::Ok();
  }

  static std::string describe(const MeshCell& c) {
    return "(" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) + ", " +
           std::to_string(c[3]) + ")";
  }

 private:
  static constexpr uint32_t kNone = UINT32_MAX;
  std::span<const MeshCell> rest_;
  std::span<const GridPoint> points_;
  std::vector<uint8_t> placed_;
  ExactStats& stats_;
  std::unordered_map<FaceKey, std::array<uint32_t, 2>, FaceKeyHash> across_;
  uint32_t pending_ = kNone;
  size_t next_seed_ = 0;
  std::vector<uint32_t> source_;
  std::vector<uint32_t> second_;  // a face's second ring
  RangeEncoder rc_;
};

}  // namespace
}  // namespace exact_cells

StatusOr<std::vector<uint8_t>> encode_exact_cells(const TetMesh& dt, std::span<const GridPoint> points,
                                                  double alpha, std::span<uint8_t> kept,
                                                  std::span<const uint32_t> order,
                                                  std::span<const MeshCell> rest, ApexRanks& ranks,
                                                  ExactFill& fill, std::vector<uint32_t>& source,
                                                  ExactStats* stats, const FitBudget& budget) {
  ExactStats local;
  ExactStats& s = stats ? *stats : local;
  s = {};
  exact_cells::Encoder side(rest, points, s);
  DTM_RETURN_IF_ERROR(side.index());
  exact_cells::Fill<exact_cells::Encoder> walk(dt, points, alpha, kept, side, fill, ranks, budget);
  const Status status = walk.run(order);
  if (walk.over_fit_budget()) {
    // Where a decoder would give up testing, every candidate counts. (14.0's
    // flips come before any fit test: `kept` is as they left it, and 11.0's
    // fill grows their cells.)
    ranks = ApexRanks::kAmongCandidates;
    return encode_exact_cells(dt, points, alpha, kept, order, rest, ranks, fill, source, stats);
  }
  if (status.code() == StatusCode::kInvalidInput) return status;
  if (!status.ok()) {
    // What the decoder would refuse is, from the encoder's side, an input
    // that is not a valid mesh on the grid.
    std::string why = status.message();
    if (why.rfind("exact cells: ", 0) == 0) why = why.substr(13);
    return invalid_input(
        "the input is not a valid tetrahedral mesh on the grid (" + why +
        "): --exact needs positively oriented cells that do not overlap, each face shared by "
        "at most two, none flat after quantization (a flat cell: raise --qbits; cells that overlap, or a "
        "face of three cells: mend the input)");
  }
  s.fit_work = walk.fit_work();
  source = std::move(side.source());
  return side.finish();
}

uint64_t keep_flipped_cells(const TetMesh& dt, std::span<const GridPoint> points,
                            std::span<const MeshCell> rest, std::span<uint8_t> kept) {
  using exact_cells::FaceKey;
  // Two input cells on the two sides of a face (x, y, z), with the corners
  // a and b off it, are a 3-2 flip of dt when dt's cells around the edge
  // (a, b) are the three (a, b) with two of x, y, z.
  std::unordered_map<FaceKey, std::array<uint32_t, 2>, exact_cells::FaceKeyHash> sides;
  sides.reserve(rest.size() * 4);
  const auto off = [](const MeshCell& c, const FaceKey& f) {
    for (uint32_t v : c)
      if (v != f[0] && v != f[1] && v != f[2]) return v;
    return c[0];
  };
  for (uint32_t i = 0; i < rest.size(); ++i)
    for (size_t k = 0; k < 4; ++k) {
      const MeshCell& c = rest[i];
      const FaceKey key = exact_cells::key_of({c[(k + 1) % 4], c[(k + 2) % 4], c[(k + 3) % 4]});
      auto [it, fresh] = sides.emplace(key, std::array<uint32_t, 2>{i, UINT32_MAX});
      if (!fresh) it->second[1] = i;
    }
  const Csr incident = vertex_cells(dt.cells, points.size());
  uint64_t flips = 0;
  std::vector<uint32_t> around;
  for (const auto& [face, two] : sides) {
    if (two[1] == UINT32_MAX) continue;
    const uint32_t a = off(rest[two[0]], face), b = off(rest[two[1]], face);
    around.clear();
    for (uint32_t c : incident.row(a))
      if (std::find(dt.cells[c].begin(), dt.cells[c].end(), b) != dt.cells[c].end()) around.push_back(c);
    if (around.size() != 3) continue;
    bool ring = true;
    for (uint32_t c : around)
      for (uint32_t v : dt.cells[c])
        ring = ring && !kept[c] && (v == a || v == b || v == face[0] || v == face[1] || v == face[2]);
    const GridPoint &x = points[face[0]], &y = points[face[1]], &z = points[face[2]];
    const int oa = orientation(x, y, z, points[a]), ob = orientation(x, y, z, points[b]);
    if (!ring || oa == 0 || ob == 0 || (oa > 0) == (ob > 0)) continue;
    for (uint32_t c : around) kept[c] = 1;
    ++flips;
  }
  return flips;
}

}  // namespace dtm
