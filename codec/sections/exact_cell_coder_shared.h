// What the exact cell coder's encoder (exact_cell_encoder.cpp) and decoder
// (exact_cell_decoder.cpp) share: the fill both sides make, face by face
// (spec/FORMAT.md §3.10), with the symbols left to a Side:
//   bool filled(AdaptiveBit&, const OpenFace&)   an input cell across the face?
//   Status apex(const OpenFace&, std::vector<uint32_t>& candidates,
//               const ApexOrder&, RankModels&, const CandidateFit&,
//               const SecondRing&, uint32_t& apex)
//   bool another_seed(AdaptiveBit&)              a cell no open face reaches?
//   Status seed(MeshCell&)                       that cell
//   Status check()                               the section not overrun
//   void added(const MeshCell&)                  a cell was added
//   bool flipped(AdaptiveBit&, const FlipCandidate&)
//                                                14.0: the flip made?
//   Status ranked_apex(const OpenFace&, ApexSearch&, const SecondRing&,
//                      uint32_t& apex)           23.0's apex
// Both sides must visit the faces identically; it is written here once.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "bitstream/range_coder.h"
#include "codec/sections/carving_coder.h"
#include "codec/sections/exact_cell_coder.h"
#include "common/csr.h"
#include "common/parallel_for.h"
#include "mesh/carving.h"
#include "mesh/geometry.h"
#include "mesh/predicates.h"
#include "mesh/topology.h"

namespace dtm::exact_cells {

using FaceKey = std::array<uint32_t, 3>;  // ascending
struct FaceKeyHash {
  size_t operator()(const FaceKey& k) const {
    uint64_t h = k[0] * 0x9E3779B97F4A7C15ull;
    h ^= (h >> 29) + k[1] * 0xBF58476D1CE4E5B9ull;
    h ^= (h >> 31) + k[2] * 0x94D049BB133111EBull;
    return static_cast<size_t>(h ^ (h >> 32));
  }
};
inline FaceKey key_of(std::array<uint32_t, 3> f) {
  std::sort(f.begin(), f.end());
  return f;
}

// The face of a positively oriented cell opposite corner k, ordered so that
// the cell lies on its negative side (its right-hand normal points out).
inline constexpr int kOutward[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
inline std::array<uint32_t, 3> outward_face(const MeshCell& c, int k) {
  return {c[static_cast<size_t>(kOutward[k][0])], c[static_cast<size_t>(kOutward[k][1])],
          c[static_cast<size_t>(kOutward[k][2])]};
}
// The same oriented face starting at its smallest corner: a triangulation
// lists a cell's corners in any order (the encoder's and the decoder's
// differ), the fill must not.
inline std::array<uint32_t, 3> from_smallest(const std::array<uint32_t, 3>& f) {
  const int s = f[0] < f[1] ? (f[0] < f[2] ? 0 : 2) : (f[1] < f[2] ? 1 : 2);
  return {f[static_cast<size_t>(s)], f[static_cast<size_t>((s + 1) % 3)],
          f[static_cast<size_t>((s + 2) % 3)]};
}
// True when b is a with the other orientation (the same three corners).
inline bool reversed(const std::array<uint32_t, 3>& a, const std::array<uint32_t, 3>& b) {
  for (int s = 0; s < 3; ++s)
    if (b[0] == a[static_cast<size_t>(s)])
      return b[1] == a[static_cast<size_t>((s + 2) % 3)] && b[2] == a[static_cast<size_t>((s + 1) % 3)];
  return false;
}

// A face with one cell so far (open), or one the fill closed or declared the
// boundary.
struct OpenFace {
  std::array<uint32_t, 3> outward{};  // seen from outside its cell, smallest corner first
  int32_t cell = 0;                   // extended numbering
  uint8_t corner = 0;                 // of that cell, the one the face lacks
  uint8_t state = 0;                  // kOpen, kClosed, kBoundary
  uint32_t next = 0;                  // the next face in its hash bucket
};
inline constexpr uint8_t kOpen = 0, kClosed = 1, kBoundary = 2;
inline constexpr uint32_t kNoFace = UINT32_MAX;

// The contexts of the filled bit. 11.0 and 12.0: a kept cell's face on the
// convex hull, one whose Delaunay cell across alpha would carve away, one
// whose cell across alpha would keep (a hole, most often), a fill cell's
// face. 13.0 (context_by_cell_across()): 0 for a kept cell's face on the
// hull; for a face with a Delaunay cell n across it (a kept cell's face, or
// a fill cell's face that is a Delaunay face), 1 + 6 x (2 x fill cell's face
// + alpha keeps n) + 3 x (a neighbour of n beside the face is kept) + n's
// shape bucket (carving_coder.h); 25 for a fill cell's face with no
// Delaunay cell across. On hand_10k (TetGen, many slivers) half the kept
// cells' faces whose cell across alpha carves away are filled, but nearly
// none of those whose cell across is flat: those lie outside the solid,
// along its surface.
inline constexpr int kFilledContexts11 = 4;
inline constexpr int kFilledContextsByCell = 2 * kShapeBuckets;
inline constexpr int kFilledContexts13 = 2 + 4 * kFilledContextsByCell;
// 23.0: 13.0's context times the face's edges' bucket (edge_bucket()): how
// many of its edges have one face declared the boundary, and whether one
// has two or more. Where the fill runs along the solid's surface, a face
// whose edges the surface already reaches is the surface's more often; on
// triceratops_10k (TetGen, 10k vertices) the decisions cost 5,032 bits
// against 13.0's 6,827.
inline constexpr int kEdgeBuckets = 6;
inline constexpr int kFilledContexts23 = kFilledContexts13 * kEdgeBuckets;
inline constexpr int kFilledContexts = std::max({kFilledContexts11, kFilledContexts13, kFilledContexts23});
// The rank, per kind of face (kept / fill cell): unary over its first
// kRankUnary values (adaptive bits: rank 0 is most of them), then
// Exp-Golomb of the rest with adaptive prefix bits.
inline constexpr int kRankUnary = 6;
inline constexpr int kRankPrefix = 16;
struct RankModels {
  std::array<AdaptiveBit, kRankUnary> unary;
  std::array<AdaptiveBit, kRankPrefix> prefix;
};
// 13.0: the rank models of kept cells' faces, fill cells' faces, and of an
// apex in the second ring; 23.0's, by how many open faces the first
// candidate that fits would close (0 to 3), or none fits (ApexSearch).
inline constexpr size_t kSecondRingRanks = 2;
inline constexpr size_t kClosingRanks = kSecondRingRanks + 1;
inline constexpr size_t kRankModels = kClosingRanks + 5;

// 23.0: per edge (its corners' numbers, the smaller in the high half), how
// many faces declared the boundary have it. Open addressing: most fills
// declare the solid's whole surface around them.
class EdgeCounts {
 public:
  EdgeCounts() : keys_(1024, kEmpty), counts_(1024, 0) {}
  uint8_t count(uint32_t a, uint32_t b) const {
    const uint64_t key = key_of(a, b);
    for (size_t i = slot(key);; i = (i + 1) & (keys_.size() - 1)) {
      if (keys_[i] == key) return counts_[i];
      if (keys_[i] == kEmpty) return 0;
    }
  }
  void add(uint32_t a, uint32_t b) {
    if (2 * (used_ + 1) > keys_.size()) grow();
    const uint64_t key = key_of(a, b);
    size_t i = slot(key);
    while (keys_[i] != key && keys_[i] != kEmpty) i = (i + 1) & (keys_.size() - 1);
    if (keys_[i] == kEmpty) keys_[i] = key, ++used_;
    if (counts_[i] < UINT8_MAX) ++counts_[i];
  }

 private:
  static constexpr uint64_t kEmpty = UINT64_MAX;  // no edge: its corners would be equal
  static uint64_t key_of(uint32_t a, uint32_t b) {
    return a < b ? uint64_t{a} << 32 | b : uint64_t{b} << 32 | a;
  }
  size_t slot(uint64_t key) const {
    const uint64_t h = key * 0x9E3779B97F4A7C15ull;
    return static_cast<size_t>(h ^ (h >> 29)) & (keys_.size() - 1);
  }
  void grow() {
    std::vector<uint64_t> keys(2 * keys_.size(), kEmpty);
    std::vector<uint8_t> counts(keys.size(), 0);
    std::swap(keys, keys_), std::swap(counts, counts_);
    for (size_t j = 0; j < keys.size(); ++j) {
      if (keys[j] == kEmpty) continue;
      size_t i = slot(keys[j]);
      while (keys_[i] != kEmpty) i = (i + 1) & (keys_.size() - 1);
      keys_[i] = keys[j], counts_[i] = counts[j];
    }
  }
  std::vector<uint64_t> keys_;
  std::vector<uint8_t> counts_;
  size_t used_ = 0;
};

// Candidates ordered as the Delaunay criterion ranks them for the face
// (a, b, c) (outward): q before p when q lies inside the sphere through a,
// b, c, p; ties (cospherical) by vertex number. Exact, so a strict order.
struct ApexOrder {
  std::span<const GridPoint> points;
  GridPoint a, b, c;
  bool operator()(uint32_t q, uint32_t p) const {
    if (q == p) return false;
    const int s = side_of_sphere(a, b, c, points[p], points[q]);
    return s > 0 || (s == 0 && q < p);
  }
};

inline void put_rank(RangeEncoder& rc, RankModels& m, uint64_t rank) {
  for (int i = 0; i < kRankUnary; ++i) {
    rc.encode(m.unary[static_cast<size_t>(i)], rank > static_cast<uint64_t>(i));
    if (rank == static_cast<uint64_t>(i)) return;
  }
  rank -= kRankUnary;
  const int e = std::bit_width(rank + 1) - 1;
  for (int i = 0; i < e; ++i) rc.encode(m.prefix[static_cast<size_t>(std::min(i, kRankPrefix - 1))], true);
  rc.encode(m.prefix[static_cast<size_t>(std::min(e, kRankPrefix - 1))], false);
  rc.encode_raw(rank + 1 - (uint64_t{1} << e), e);
}
inline Status get_rank(RangeDecoder& rc, RankModels& m, uint64_t& rank) {
  for (int i = 0; i < kRankUnary; ++i)
    if (!rc.decode(m.unary[static_cast<size_t>(i)])) {
      rank = static_cast<uint64_t>(i);
      return Status::Ok();
    }
  int e = 0;
  while (rc.decode(m.prefix[static_cast<size_t>(std::min(e, kRankPrefix - 1))]))
    if (++e > 32) return {StatusCode::kCorrupt, "exact cells: an apex rank out of range"};
  rank = ((uint64_t{1} << e) | rc.decode_raw(e)) - 1 + kRankUnary;
  return Status::Ok();
}

// 14.0 (spec/FORMAT.md §3.10): a 3-2 flip of kept cells, the three cells
// around `edge` (ascending) traded for the two through `ring` (ascending)
// with an edge corner each.
struct FlipCandidate {
  std::array<uint32_t, 2> edge;
  std::array<uint32_t, 3> ring;
};
// Its flag's context: the least squared quality of the three cells before
// (D^2 / S^3 times 7776, squared_quality() in carving_coder.h) in octaves
// of the quality, 0 (at least 1/2) to 5 (below 1/32); and the least of the
// two after over it, 0 when not larger, else 1 to 4 for below 2, 4, 8 and
// more times the quality. A mesher's optimiser flips to lift a sliver:
// hand_10k's flips are rare among its candidates (675 of 7,222) but not
// among those that lift a flat cell much (research/exact_regions.md).
inline constexpr int kFlipLiftBuckets = 5;
inline constexpr int kFlipContexts = 6 * kFlipLiftBuckets;
inline int flip_context(double before, double after) {
  int e = 0;
  std::frexp(7776 * before, &e);
  const int low = before > 0 ? std::min(5, std::max(0, -e) / 2) : 5;
  if (!(after > before)) return low * kFlipLiftBuckets;
  if (before <= 0) return low * kFlipLiftBuckets + kFlipLiftBuckets - 1;
  std::frexp(after / before, &e);  // e >= 1: the squared ratio is in [2^(e-1), 2^e)
  return low * kFlipLiftBuckets + std::min(kFlipLiftBuckets - 1, (e - 1) / 2 + 1);
}

inline Status corrupt(const std::string& why) { return {StatusCode::kCorrupt, "exact cells: " + why}; }

// What the overlap check (exact_cell_overlap.cpp) lets a fill cost
// (spec/FORMAT.md §3.10): the Delaunay cells a fill cell's interior meets,
// on average (plus 4096 in all) and at most; the comparisons of fill cells
// meeting one Delaunay cell, per meeting (plus 65536); the Delaunay cells
// tested against a fill cell, on average (plus 65536). On the corpus's
// meshes, gmsh's part and bunny_1m: 2.8-4.3 meetings a fill cell, 49 at
// most (hand_10k's slivers), 0.7-2.4 comparisons a meeting, 4.5-10.7 tests
// a fill cell.
inline constexpr uint64_t kMeetingsPerCell = 16;
inline constexpr size_t kMaxMeetings = 1024;
inline constexpr uint64_t kComparisonsPerMeeting = 32;
inline constexpr uint64_t kTestsPerCell = 64;

// 12.0: what ranking the apex among the candidates that fit (spec/FORMAT.md
// §3.10) lets a section cost (FitBudget, exact_cell_coder.h). Testing a
// candidate q for the face (a, b, c) costs, as both sides count it, the
// fill cells at a, b and c (each at most one test of the cell (a, b, c, q)
// against it). The corpus's meshes, gmsh's and Netgen's spend 2.5-42 a
// face against the 1024 allowed.

// Refuses a fill whose cells overlap each other or a kept Delaunay cell
// without sharing a face (exact_cell_overlap.cpp). `incident`: per vertex,
// dt's cells around it.
Status check_cells_apart(const TetMesh& dt, std::span<const GridPoint> points, std::span<const uint8_t> kept,
                         const ExactFill& fill, const Csr& incident);

template <class Side>
class Fill {
 public:
  // `ranks`: the stream's version's symbols (ApexRanks, exact_cell_coder.h).
  Fill(const TetMesh& dt, std::span<const GridPoint> points, double alpha, std::span<uint8_t> kept,
       Side& side, ExactFill& out, ApexRanks ranks, const FitBudget& budget = {})
      : dt_(dt),
        points_(points),
        alpha_(alpha),
        kept_(kept),
        side_(side),
        out_(out),
        only_fitting_(ranks != ApexRanks::kAmongCandidates),
        in_context_(ranks >= ApexRanks::kAmongFittingInContext),
        flips_(ranks >= ApexRanks::kAfterFlips),
        closing_first_(ranks == ApexRanks::kClosingFirst),
        budget_(budget) {
    seen_.assign(points.size(), 0);
    bucket_.assign(1024, kNoFace);
    incident_ = vertex_cells(dt.cells, points.size());
    if (only_fitting_) fill_at_.assign(points.size(), kNoSlot), fill_count_.assign(points.size(), 0);
  }

  // What a side asks of one face's candidates: whether the candidate's
  // cell fits (12.0), or, in 11.0 (on() false), nothing.
  class CandidateFit {
   public:
    CandidateFit(Fill& fill, const std::array<uint32_t, 3>& face) : fill_(fill), face_(face) {}
    bool on() const { return fill_.only_fitting_; }
    Status operator()(uint32_t q, bool& fits) const { return fill_.fits(face_, q, fits); }

   private:
    Fill& fill_;
    std::array<uint32_t, 3> face_;
  };

  // 13.0: where an apex that is not a candidate is ranked (second_ring()).
  class SecondRing {
   public:
    SecondRing(Fill& fill, const std::array<uint32_t, 3>& face) : fill_(fill), face_(face) {}
    bool on() const { return fill_.in_context_; }
    RankModels& models() const { return fill_.rank_[kSecondRingRanks]; }
    Status operator()(std::vector<uint32_t>& out) const { return fill_.second_ring(face_, out); }

   private:
    Fill& fill_;
    std::array<uint32_t, 3> face_;
  };

  // 23.0 (spec/FORMAT.md §3.10): the candidates that fit, one at a time,
  // in the order an apex is ranked in: the first that fits in the Delaunay
  // order, then the others by how many open faces their cell would close
  // (most first), then the Delaunay order. An input cell fills the gaps
  // beside it: on the corpus the apex closes as many as the most any
  // candidate does far more often than the Delaunay order's second
  // candidate is the apex. Both sides ask for them until the apex (the
  // encoder) or the rank (the decoder): each candidate is tested once, the
  // same ones on both sides.
  class ApexSearch {
   public:
    ApexSearch(Fill& fill, const std::array<uint32_t, 3>& face, std::vector<uint32_t>& candidates,
               const ApexOrder& less)
        : fill_(fill), face_(face), candidates_(candidates), less_(less) {}
    // The next candidate that fits, or `found` false when none is left.
    Status next(uint32_t& q, bool& found) {
      found = false;
      while (next_ < candidates_.size()) {
        const size_t i = next_++;
        const auto at = candidates_.begin() + static_cast<std::ptrdiff_t>(i);
        if (first_ == kNone) {
          // The Delaunay order, picked one at a time (the first candidate
          // most often fits), past a few sorted at once.
          constexpr size_t kPicks = 8;
          if (i < kPicks)
            std::iter_swap(at, std::min_element(at, candidates_.end(), less_));
          else if (i == kPicks)
            std::sort(at, candidates_.end(), less_);
        } else if (i == first_ + 1) {
          sort_rest();
        }
        q = candidates_[i];
        int closes = 0;
        bool fits = fill_.closes(face_, q, closes);
        if (fits) DTM_RETURN_IF_ERROR(fill_.fits(face_, q, fits));
        if (!fits) continue;
        if (first_ == kNone) first_ = i, first_closes_ = closes;
        found = true;
        return Status::Ok();
      }
      return Status::Ok();
    }
    // The rank's models: by how many open faces the first candidate that
    // fits closes (after the first next()).
    RankModels& models() const { return fill_.rank_[kClosingRanks + static_cast<size_t>(first_closes_ + 1)]; }
    const ApexOrder& less() const { return less_; }
    bool holds(uint32_t q) const {
      return std::find(candidates_.begin(), candidates_.end(), q) != candidates_.end();
    }

   private:
    static constexpr size_t kNone = SIZE_MAX;
    // The candidates after the first that fits, by the faces they close.
    void sort_rest() {
      const auto rest = candidates_.begin() + static_cast<std::ptrdiff_t>(first_ + 1);
      std::vector<std::pair<int, uint32_t>>& keyed = fill_.keyed_;
      keyed.clear();
      for (auto it = rest; it != candidates_.end(); ++it) {
        int closes = 0;
        fill_.closes(face_, *it, closes);  // (a blocked one's count is partial: next() passes it over)
        keyed.push_back({closes, *it});
      }
      std::sort(keyed.begin(), keyed.end(),
                [&](const std::pair<int, uint32_t>& x, const std::pair<int, uint32_t>& y) {
                  return x.first != y.first ? x.first > y.first : less_(x.second, y.second);
                });
      for (size_t k = 0; k < keyed.size(); ++k) rest[static_cast<std::ptrdiff_t>(k)] = keyed[k].second;
    }
    Fill& fill_;
    std::array<uint32_t, 3> face_;
    std::vector<uint32_t>& candidates_;
    const ApexOrder& less_;
    size_t next_ = 0, first_ = kNone;
    int first_closes_ = -1;
  };

  // True when the last run stopped at the fit tests' budget (the encoder
  // then writes the section without them).
  bool over_fit_budget() const { return over_fit_budget_; }
  uint64_t fit_work() const { return fit_work_; }

  Status run(std::span<const uint32_t> order) {
    out_ = {};
    const auto cells = static_cast<uint32_t>(dt_.cells.size());
    // 14.0: the flips first; their cells join the fill once the kept
    // cells' faces are open, closing the faces they meet.
    std::vector<MeshCell> flipped;
    if (flips_) DTM_RETURN_IF_ERROR(flip(order, flipped));
    // Per kept cell, the faces it opens (bit k: the cell across the face
    // opposite corner k is not kept): each cell on its own, on every core;
    // most open none.
    std::vector<uint8_t> opens(cells, 0);
    constexpr size_t kBlock = 4096;
    parallel_for((cells + kBlock - 1) / kBlock,
                 [&](size_t block) {
                   for (size_t c = block * kBlock; c < std::min<size_t>(cells, block * kBlock + kBlock);
                        ++c) {
                     if (!kept_[c]) continue;
                     for (int k = 0; k < 4; ++k) {
                       const int32_t n = dt_.neighbors[c][static_cast<size_t>(k)];
                       if (n < 0 || !kept_[static_cast<size_t>(n)]) opens[c] |= static_cast<uint8_t>(1 << k);
                     }
                   }
                 },
                 2);
    // The few cells that open faces, in the order, found on every core (a
    // pass over every cell's flag, anywhere in memory); each then asked for
    // some cells ahead.
    const std::vector<uint32_t> opening = collect_in_order<uint32_t>(
        order.size(), size_t{1} << 16, [&](size_t first, size_t last, std::vector<uint32_t>& out) {
          for (size_t i = first; i < last; ++i)
            if (order[i] < cells && opens[order[i]]) out.push_back(order[i]);
        });
    for (size_t i = 0; i < opening.size(); ++i) {
      constexpr size_t kAhead = 16;
      if (i + kAhead < opening.size()) __builtin_prefetch(&dt_.cells[opening[i + kAhead]]);
      const uint32_t c = opening[i];
      // Its faces by the corner they lack, in vertex number order.
      std::array<int, 4> corners = {0, 1, 2, 3};
      std::sort(corners.begin(), corners.end(), [&](int x, int y) {
        return dt_.cells[c][static_cast<size_t>(x)] < dt_.cells[c][static_cast<size_t>(y)];
      });
      for (int k : corners)
        if (opens[c] >> k & 1)
          open(outward_face(dt_.cells[c], k), static_cast<int32_t>(c), static_cast<uint8_t>(k));
    }
    for (const MeshCell& c : flipped) DTM_RETURN_IF_ERROR(add(c));
    std::vector<uint32_t> candidates;
    while (true) {
      while (head_ < queue_.size()) {
        OpenFace& f = faces_[queue_[head_++]];
        if (f.state != kOpen) continue;
        DTM_RETURN_IF_ERROR(side_.check());
        const int x = closing_first_ ? context_by_cell_across(f) * kEdgeBuckets + edge_bucket(f.outward)
                      : in_context_  ? context_by_cell_across(f)
                                     : context(f);
        if (!side_.filled(filled_[static_cast<size_t>(x)], f)) {
          f.state = kBoundary;
          if (closing_first_)
            for (size_t k = 0; k < 3; ++k) boundary_edges_.add(f.outward[k], f.outward[(k + 1) % 3]);
          continue;
        }
        gather(f, candidates);
        const ApexOrder less{points_, points_[f.outward[0]], points_[f.outward[1]], points_[f.outward[2]]};
        uint32_t apex = 0;
        // f is in faces_, which add() may grow: copy what it needs first.
        const std::array<uint32_t, 3> face = f.outward;
        ++faces_given_cells_;
        if (closing_first_) {
          ApexSearch search(*this, face, candidates, less);
          DTM_RETURN_IF_ERROR(side_.ranked_apex(f, search, SecondRing(*this, face), apex));
        } else {
          DTM_RETURN_IF_ERROR(side_.apex(f, candidates, less,
                                         rank_[static_cast<size_t>(f.cell >= int64_t{cells})],
                                         CandidateFit(*this, face), SecondRing(*this, face), apex));
        }
        DTM_RETURN_IF_ERROR(add({face[0], face[1], face[2], apex}));
      }
      DTM_RETURN_IF_ERROR(side_.check());
      if (!side_.another_seed(seed_)) break;
      MeshCell s{};
      DTM_RETURN_IF_ERROR(side_.seed(s));
      DTM_RETURN_IF_ERROR(add(s));
    }
    DTM_RETURN_IF_ERROR(side_.check());
    return check_cells_apart(dt_, points_, kept_, out_, incident_);
  }

 private:
  // 14.0 (spec/FORMAT.md §3.10): a flag for every valid 3-2 flip of the
  // kept cells, visited in the kept cells' order (each edge at the first of
  // its three cells, a cell's edges by their corners); a flip whose cells
  // an earlier flip took is passed over. A flipped edge's three cells are
  // no longer kept; `flipped` receives its two cells, the one with the
  // lesser edge corner first, each as (the ring seen from outside it, the
  // corner).
  Status flip(std::span<const uint32_t> order, std::vector<MeshCell>& flipped) {
    const size_t cells = dt_.cells.size();
    // Per kept cell, bit j set when the j-th pair of its corners
    // (kCornerPairs) is the ring's side of a flip, and per bit set, in the
    // cells' coding order, what its flag needs of the geometry: the ring's
    // third corner and the flag's context. All found on every core, in
    // blocks of the order, so that the pass that codes the flags reads
    // neither the neighbours' cells nor the points (that pass held 5% of
    // bunny_1m's exact decode on one thread when it found them itself).
    // `order` is a permutation of the cells (canonical_cell_order): each
    // cell's bits are written once. A cell's corners and its neighbours'
    // lie anywhere in memory: asked for some places ahead, in two steps.
    std::vector<uint8_t> rings(cells, 0);
    constexpr size_t kBlock = 4096, kAhead = 16;
    const size_t blocks = (order.size() + kBlock - 1) / kBlock;
    std::vector<std::vector<PairGeometry>> geometry(blocks);
    std::vector<std::vector<uint32_t>> ringed(blocks);  // per block, its cells with bits, in order
    parallel_for(
        blocks,
        [&](size_t block) {
          const size_t end = std::min(order.size(), block * kBlock + kBlock);
          for (size_t i = block * kBlock; i < end; ++i) {
            if (i + 2 * kAhead < end && order[i + 2 * kAhead] < cells) {
              __builtin_prefetch(&dt_.neighbors[order[i + 2 * kAhead]]);
              __builtin_prefetch(&dt_.cells[order[i + 2 * kAhead]]);
            }
            if (i + kAhead < end && order[i + kAhead] < cells)
              for (int32_t n : dt_.neighbors[order[i + kAhead]])
                if (n >= 0) __builtin_prefetch(&dt_.cells[static_cast<size_t>(n)]);
            const uint32_t c = order[i];
            if (c >= cells || !kept_[c]) continue;
            std::array<uint32_t, 4> far{};
            rings[c] = flip_pairs(c, far);
            if (rings[c]) ringed[block].push_back(c);
            for (size_t j = 0; j < kCornerPairs.size(); ++j)
              if (rings[c] >> j & 1) {
                const FlipCandidate f = flip_candidate(c, j, far);
                geometry[block].push_back({f.ring, flip_context_of(f)});
              }
          }
        },
        2);
    constexpr uint8_t kVisited = 0x80;
    struct Here {
      FlipCandidate f;
      std::array<uint32_t, 3> three;  // its cells
      uint8_t context;
    };
    std::vector<Here> here;
    for (size_t block = 0; block < blocks; ++block) {
      const std::vector<uint32_t>& cells_here = ringed[block];
      const std::vector<PairGeometry>& listed = geometry[block];  // their pairs', in turn
      size_t next = 0;
      for (size_t i = 0; i < cells_here.size(); ++i) {
        if (i + kAhead < cells_here.size()) {
          __builtin_prefetch(&dt_.cells[cells_here[i + kAhead]]);
          __builtin_prefetch(&dt_.neighbors[cells_here[i + kAhead]]);
        }
        const uint32_t c = cells_here[i];
        here.clear();
        const MeshCell& v = dt_.cells[c];
        for (size_t j = 0; j < kCornerPairs.size(); ++j) {
          if (!(rings[c] >> j & 1)) continue;
          const PairGeometry g = listed[next++];
          const auto [x, y] = kCornerPairs[j];
          const auto nx = static_cast<uint32_t>(dt_.neighbors[c][x]),
                     ny = static_cast<uint32_t>(dt_.neighbors[c][y]);
          if ((rings[nx] | rings[ny]) & kVisited) continue;  // given its flag at an earlier cell
          FlipCandidate f{};
          for (size_t k = 0, e = 0; k < 4; ++k)
            if (k != x && k != y) f.edge[e++] = v[k];
          std::sort(f.edge.begin(), f.edge.end());
          f.ring = g.ring;
          here.push_back({f, {c, nx, ny}, g.context});
        }
        rings[c] |= kVisited;
        std::sort(here.begin(), here.end(), [](const Here& a, const Here& b) {
          return std::tie(a.f.edge, a.f.ring) < std::tie(b.f.edge, b.f.ring);
        });
        for (const auto& [f, three, context] : here) {
          if (!kept_[three[0]] || !kept_[three[1]] || !kept_[three[2]]) continue;
          DTM_RETURN_IF_ERROR(side_.check());
          if (!side_.flipped(flip_[context], f)) continue;
          for (uint32_t t : three) kept_[t] = 0;
          const std::array<GridPoint, 3> r = {points_[f.ring[0]], points_[f.ring[1]], points_[f.ring[2]]};
          for (uint32_t corner : f.edge) {
            const bool above = orientation(r[0], r[1], r[2], points_[corner]) > 0;
            flipped.push_back(above ? MeshCell{f.ring[0], f.ring[1], f.ring[2], corner}
                                    : MeshCell{f.ring[0], f.ring[2], f.ring[1], corner});
          }
        }
      }
    }
    return Status::Ok();
  }

  // What a flip's flag needs of the geometry (flip()).
  struct PairGeometry {
    std::array<uint32_t, 3> ring;  // ascending
    uint8_t context;               // flip_context()
  };

  // The bits of flip(): the valid flips whose three cells are all kept;
  // `far` as valid_flips() gives it.
  uint8_t flip_pairs(size_t cell, std::array<uint32_t, 4>& far) const {
    uint8_t bits = valid_flips(dt_, points_, cell, far);
    for (size_t j = 0; j < kCornerPairs.size(); ++j) {
      const auto [x, y] = kCornerPairs[j];
      if ((bits >> j & 1) && (!kept_[static_cast<size_t>(dt_.neighbors[cell][x])] ||
                              !kept_[static_cast<size_t>(dt_.neighbors[cell][y])]))
        bits = static_cast<uint8_t>(bits & ~(1 << j));
    }
    return bits;
  }

  // The flip of `cell`'s pair j (a bit of valid_flips()), its edge and ring ascending.
  FlipCandidate flip_candidate(size_t cell, size_t j, const std::array<uint32_t, 4>& far) const {
    const MeshCell& v = dt_.cells[cell];
    const auto [x, y] = kCornerPairs[j];
    FlipCandidate f{};
    for (size_t k = 0, e = 0; k < 4; ++k)
      if (k != x && k != y) f.edge[e++] = v[k];
    f.ring = {v[x], v[y], far[x]};
    std::sort(f.edge.begin(), f.edge.end());
    std::sort(f.ring.begin(), f.ring.end());
    return f;
  }

  // Its flag's context: the least quality of the three cells before and of
  // the two after (flip_context()).
  uint8_t flip_context_of(const FlipCandidate& f) const {
    const std::array<GridPoint, 3> r = {points_[f.ring[0]], points_[f.ring[1]], points_[f.ring[2]]};
    const GridPoint &p = points_[f.edge[0]], &q = points_[f.edge[1]];
    double before = squared_quality(p, q, r[0], r[1]);
    before = std::min({before, squared_quality(p, q, r[1], r[2]), squared_quality(p, q, r[0], r[2])});
    const double after = std::min(squared_quality(r[0], r[1], r[2], p), squared_quality(r[0], r[1], r[2], q));
    return static_cast<uint8_t>(flip_context(before, after));
  }

  // The faces in one array, found through a hash of their corners with
  // its chains in the faces themselves (with a node-based hash map, an
  // allocation a face, opening and filling took 2.3 s at a million
  // vertices, 1.2 s now; a list per smallest corner was as fast, but a
  // hostile section could make one vertex's list as long as the level).
  size_t bucket_of(const FaceKey& key) const { return FaceKeyHash{}(key) & (bucket_.size() - 1); }
  void open(const std::array<uint32_t, 3>& outward, int32_t cell, uint8_t corner) {
    if (faces_.size() >= bucket_.size()) {  // at most one face a bucket on average
      bucket_.assign(2 * bucket_.size(), kNoFace);
      for (uint32_t id = 0; id < faces_.size(); ++id)
        faces_[id].next = std::exchange(bucket_[bucket_of(key_of(faces_[id].outward))], id);
    }
    OpenFace f{from_smallest(outward), cell, corner, kOpen, 0};
    const auto id = static_cast<uint32_t>(faces_.size());
    f.next = std::exchange(bucket_[bucket_of(key_of(outward))], id);
    faces_.push_back(f);
    queue_.push_back(id);
  }
  uint32_t find(const FaceKey& key) const {
    for (uint32_t id = bucket_[bucket_of(key)]; id != kNoFace; id = faces_[id].next) {
      const std::array<uint32_t, 3>& o = faces_[id].outward;
      if (o[0] == key[0] && ((o[1] == key[1] && o[2] == key[2]) || (o[1] == key[2] && o[2] == key[1])))
        return id;
    }
    return kNoFace;
  }

  // 13.0's context (kFilledContexts13): from the Delaunay cell across the
  // face, when there is one.
  int context_by_cell_across(const OpenFace& f) const {
    const auto cells = static_cast<int64_t>(dt_.cells.size());
    const std::array<uint32_t, 3>& face = f.outward;
    const bool of_fill = f.cell >= cells;
    const int32_t across =
        of_fill ? delaunay_cell_beyond(face) : dt_.neighbors[static_cast<size_t>(f.cell)][f.corner];
    if (across < 0) return of_fill ? kFilledContexts13 - 1 : 0;
    const MeshCell& n = dt_.cells[static_cast<size_t>(across)];
    // Its neighbours across its faces through its corner off the face.
    bool kept_beside = false;
    for (size_t k = 0; k < 4; ++k) {
      if (n[k] != face[0] && n[k] != face[1] && n[k] != face[2]) continue;
      const int32_t m = dt_.neighbors[static_cast<size_t>(across)][k];
      kept_beside = kept_beside || (m >= 0 && kept_[static_cast<size_t>(m)]);
    }
    const int alpha_keeps = kept_by_alpha(points_, n, alpha_) ? 1 : 0;
    const int shape = shape_bucket({points_[n[0]], points_[n[1]], points_[n[2]], points_[n[3]]});
    return 1 + kFilledContextsByCell * (2 * of_fill + alpha_keeps) + kShapeBuckets * kept_beside + shape;
  }

  // The Delaunay cell with the face (a, b, c) (outward) on its outer side,
  // or -1 when the face is not one of DT(V_0)'s (or lies on its hull).
  int32_t delaunay_cell_beyond(const std::array<uint32_t, 3>& face) const {
    for (uint32_t c : incident_.row(face[0])) {
      const MeshCell& cell = dt_.cells[c];
      uint32_t off = 0;
      int on = 0;
      for (uint32_t v : cell) {
        if (v == face[0] || v == face[1] || v == face[2])
          ++on;
        else
          off = v;
      }
      if (on == 3 && orientation(points_[face[0]], points_[face[1]], points_[face[2]], points_[off]) > 0)
        return static_cast<int32_t>(c);
    }
    return -1;
  }

  // 13.0 (spec/FORMAT.md §3.10): the face's second ring, where an apex that
  // is not a candidate is ranked. The first ring is the corners of the
  // Delaunay cells at a, b or c (both sides of the face); the second, the
  // corners of the Delaunay cells at a vertex of the first that are not in
  // it, on the face's outer side. Its work (the cells read) counts against
  // the fit tests' budget: a hostile section may ask for it at every face.
  Status second_ring(const std::array<uint32_t, 3>& face, std::vector<uint32_t>& out) {
    out.clear();
    if (++stamp_ == 0) std::fill(seen_.begin(), seen_.end(), 0), stamp_ = 1;
    ring_.clear();
    for (uint32_t v : face) seen_[v] = stamp_;
    for (uint32_t v : face)
      for (uint32_t cell : incident_.row(v))
        for (uint32_t w : dt_.cells[cell])
          if (seen_[w] != stamp_) seen_[w] = stamp_, ring_.push_back(w);
    for (uint32_t w : ring_) fit_work_ += incident_.row(w).size();
    if (fit_work_ > budget_.per_face * faces_given_cells_ + budget_.slack) {
      over_fit_budget_ = true;
      return corrupt("its apexes' second rings cost too much");
    }
    const GridPoint &a = points_[face[0]], &b = points_[face[1]], &c = points_[face[2]];
    for (uint32_t w : ring_)
      for (uint32_t cell : incident_.row(w))
        for (uint32_t u : dt_.cells[cell]) {
          if (seen_[u] == stamp_) continue;
          seen_[u] = stamp_;
          if (orientation(a, b, c, points_[u]) > 0) out.push_back(u);
        }
    return Status::Ok();
  }

  // 23.0's bucket of a face (kEdgeBuckets): of its edges, how many have
  // one face declared the boundary (0, 1, 2 or more), and 3 more when one
  // has two or more.
  int edge_bucket(const std::array<uint32_t, 3>& face) const {
    int one = 0, more = 0;
    for (size_t k = 0; k < 3; ++k) {
      const uint8_t n = boundary_edges_.count(face[k], face[(k + 1) % 3]);
      one += n == 1, more += n >= 2;
    }
    return std::min(one, 2) + 3 * (more > 0);
  }

  // 23.0: how many open faces the cell (face, q) would close (its faces
  // through q that are open, with their cell on the other side); false when
  // one of those faces, held in the table, is declared the boundary, closed
  // already, or open with its cell on the same side (add() would refuse the
  // cell; so it would for a face between two kept cells, which the table
  // does not hold and which does not block here).
  bool closes(const std::array<uint32_t, 3>& face, uint32_t q, int& count) const {
    count = 0;
    const MeshCell cell = {face[0], face[1], face[2], q};
    for (int k = 0; k < 3; ++k) {
      const std::array<uint32_t, 3> side = outward_face(cell, k);
      const uint32_t id = find(key_of(side));
      if (id == kNoFace) continue;
      if (faces_[id].state != kOpen || !reversed(faces_[id].outward, side)) return false;
      ++count;
    }
    return true;
  }

  int context(const OpenFace& f) const {
    if (f.cell >= static_cast<int64_t>(dt_.cells.size())) return 3;
    const int32_t n = dt_.neighbors[static_cast<size_t>(f.cell)][f.corner];
    if (n < 0) return 0;
    return kept_by_alpha(points_, dt_.cells[static_cast<size_t>(n)], alpha_) ? 2 : 1;
  }

  // The Delaunay neighbours of the face's corners on its outer side; of a
  // kept cell's face, not the corner of the Delaunay cell across it (that
  // cell is not an input cell, or it would be kept).
  void gather(const OpenFace& open, std::vector<uint32_t>& out) const {
    const std::array<uint32_t, 3>& f = open.outward;
    out.clear();
    // Each vertex once (a stamp per gathering; the order of the list is
    // not the candidates' order, which ApexOrder alone sets).
    if (++stamp_ == 0) std::fill(seen_.begin(), seen_.end(), 0), stamp_ = 1;
    for (uint32_t v : f) seen_[v] = stamp_;
    const GridPoint &a = points_[f[0]], &b = points_[f[1]], &c = points_[f[2]];
    // The cells lie anywhere in memory: all of them asked for first, so
    // that the walk below waits for them together, not one by one (the
    // fill's own samples at bunny_1m's level 0, perf: 0.69 s to 0.51 s;
    // asking for the cells of the faces a few ahead in the queue gained
    // nothing).
    for (uint32_t v : f)
      for (uint32_t cell : incident_.row(v)) __builtin_prefetch(&dt_.cells[cell]);
    for (uint32_t v : f)
      for (uint32_t cell : incident_.row(v))
        for (uint32_t w : dt_.cells[cell]) {
          if (seen_[w] == stamp_) continue;
          seen_[w] = stamp_;
          if (orientation(a, b, c, points_[w]) > 0) out.push_back(w);
        }
    if (open.cell >= static_cast<int64_t>(dt_.cells.size())) return;
    const int32_t n = dt_.neighbors[static_cast<size_t>(open.cell)][open.corner];
    if (n < 0) return;
    for (uint32_t w : dt_.cells[static_cast<size_t>(n)])
      if (w != f[0] && w != f[1] && w != f[2]) std::erase(out, w);
  }

  // 12.0 (spec/FORMAT.md §3.10): true when the interior of the cell
  // (a, b, c, q) meets no cell the fill has added at a, b or c. (Testing
  // the kept Delaunay cells at a, b, c and q too took hand_10k's section
  // from 1319 to 1221 bytes, but made bunny_100k's decode 9% slower: they
  // are ten times as many.) Its work is counted by the cells at the face's
  // corners, the same on both sides whatever order they test them.
  Status fits(const std::array<uint32_t, 3>& face, uint32_t q, bool& fits) {
    for (uint32_t v : face) fit_work_ += fill_count_[v];
    if (fit_work_ > budget_.per_face * faces_given_cells_ + budget_.slack) {
      over_fit_budget_ = true;
      return corrupt("its apexes' candidates cost too many overlap tests");
    }
    if (face_cells_for_ != faces_given_cells_) gather_face_cells(face);
    fits = true;
    if (face_cells_.empty()) return Status::Ok();
    const std::array<GridPoint, 4> cell = {points_[face[0]], points_[face[1]], points_[face[2]], points_[q]};
    // Most cells beside the new one lie on the outer side of one of its
    // faces through q (a plane a few products decide), the rest are tested
    // whole.
    const std::array<FacePlane, 3> sides = {FacePlane(cell[1], cell[2], cell[3]),
                                            FacePlane(cell[0], cell[3], cell[2]),
                                            FacePlane(cell[0], cell[1], cell[3])};
    for (const auto& m : face_cells_) {
      bool apart = false;
      for (const FacePlane& side : sides)
        apart = apart || (side.height(m[0]) >= 0 && side.height(m[1]) >= 0 && side.height(m[2]) >= 0 &&
                          side.height(m[3]) >= 0);
      if (!apart && interiors_meet(cell, m)) {
        fits = false;
        return Status::Ok();
      }
    }
    return Status::Ok();
  }

  // The face's plane, heights above it scaled by its normal's length
  // (exact: the normal's components are below 2^51, a height below 2^77).
  struct FacePlane {
    GridPoint origin;
    int64_t nx = 0, ny = 0, nz = 0;
    FacePlane() = default;
    FacePlane(const GridPoint& a, const GridPoint& b, const GridPoint& c) : origin(a) {
      const int64_t ux = int64_t{b.x} - a.x, uy = int64_t{b.y} - a.y, uz = int64_t{b.z} - a.z;
      const int64_t vx = int64_t{c.x} - a.x, vy = int64_t{c.y} - a.y, vz = int64_t{c.z} - a.z;
      nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    }
    Int128 height(const GridPoint& p) const {
      return Int128{nx} * (int64_t{p.x} - origin.x) + Int128{ny} * (int64_t{p.y} - origin.y) +
             Int128{nz} * (int64_t{p.z} - origin.z);
    }
  };

  // The fill cells at the face's corners that reach past its plane, where
  // every candidate's cell lies (the others cannot meet it), each once:
  // gathered once a face, tested for each candidate.
  void gather_face_cells(const std::array<uint32_t, 3>& face) {
    face_cells_for_ = faces_given_cells_;
    const FacePlane plane(points_[face[0]], points_[face[1]], points_[face[2]]);
    face_cells_.clear();
    for (size_t k = 0; k < 3; ++k)
      for (uint32_t s = fill_at_[face[k]]; s != kNoSlot; s = fill_next_[s]) {
        const MeshCell& m = out_.cells[s / 4];
        std::array<GridPoint, 4> corners{};
        bool above = false, earlier = false;
        for (size_t i = 0; i < 4; ++i) {
          for (size_t j = 0; j < k; ++j) earlier = earlier || m[i] == face[j];  // gathered already
          corners[i] = points_[m[i]];
          above = above || plane.height(corners[i]) > 0;
        }
        if (above && !earlier) face_cells_.push_back(corners);
      }
  }

  // True when the face is one between two kept Delaunay cells.
  bool kept_face(const FaceKey& key) const {
    for (uint32_t c : incident_.row(key[0])) {
      if (!kept_[c]) continue;
      const MeshCell& cell = dt_.cells[c];
      if (std::find(cell.begin(), cell.end(), key[1]) != cell.end() &&
          std::find(cell.begin(), cell.end(), key[2]) != cell.end())
        return true;
    }
    return false;
  }

  Status add(const MeshCell& cell) {
    const uint64_t n = points_.size();
    if (out_.cells.size() >= kMaxFillCellsPerVertex * n)
      return corrupt("more cells than " + std::to_string(kMaxFillCellsPerVertex) + " a vertex");
    for (int i = 0; i < 4; ++i) {
      if (cell[static_cast<size_t>(i)] >= n) return corrupt("a cell names a vertex that does not exist");
      for (int j = 0; j < i; ++j)
        if (cell[static_cast<size_t>(i)] == cell[static_cast<size_t>(j)])
          return corrupt("a cell names one vertex twice");
    }
    if (orientation(points_[cell[0]], points_[cell[1]], points_[cell[2]], points_[cell[3]]) <= 0)
      return corrupt("a cell that is flat or on the inner side of its face");
    const auto self = static_cast<int32_t>(dt_.cells.size() + out_.cells.size());
    out_.cells.push_back(cell);
    out_.neighbours.push_back({-1, -1, -1, -1});
    const size_t i = out_.cells.size() - 1;
    // The four faces' hash buckets, then their chains' first faces, asked
    // for together before they are looked up one by one (both anywhere in
    // memory: 60% of this function's samples at bunny_1m's level 0 waited
    // on them).
    std::array<std::array<uint32_t, 3>, 4> cell_faces{};
    std::array<FaceKey, 4> keys{};
    for (size_t k = 0; k < 4; ++k) {
      cell_faces[k] = outward_face(cell, static_cast<int>(k));
      keys[k] = key_of(cell_faces[k]);
      __builtin_prefetch(&bucket_[bucket_of(keys[k])]);
    }
    for (const FaceKey& key : keys)
      if (const uint32_t first = bucket_[bucket_of(key)]; first != kNoFace)
        __builtin_prefetch(&faces_[first]);
    for (int k = 0; k < 4; ++k) {
      const std::array<uint32_t, 3>& face = cell_faces[static_cast<size_t>(k)];
      const FaceKey& key = keys[static_cast<size_t>(k)];
      const uint32_t id = find(key);
      if (id == kNoFace) {
        if (kept_face(key)) return corrupt("a face of three cells");
        open(face, self, static_cast<uint8_t>(k));
        continue;
      }
      OpenFace& g = faces_[id];
      if (g.state == kClosed) return corrupt("a face of three cells");
      if (g.state == kBoundary) return corrupt("a cell across a face given as the boundary");
      if (!reversed(g.outward, face)) return corrupt("two cells on one side of a face");
      g.state = kClosed;
      out_.neighbours[i][static_cast<size_t>(k)] = g.cell;
      if (g.cell < static_cast<int64_t>(dt_.cells.size()))
        out_.links.push_back({static_cast<uint32_t>(g.cell), g.corner, self});
      else
        out_.neighbours[static_cast<size_t>(g.cell) - dt_.cells.size()][g.corner] = self;
    }
    if (only_fitting_) {
      // The new cell at each of its corners, a list through slots 4i + k.
      fill_next_.resize(4 * out_.cells.size());
      for (size_t k = 0; k < 4; ++k) {
        const uint32_t v = cell[k];
        fill_next_[4 * i + k] = std::exchange(fill_at_[v], static_cast<uint32_t>(4 * i + k));
        ++fill_count_[v];
      }
    }
    side_.added(cell);
    return Status::Ok();
  }

  const TetMesh& dt_;
  std::span<const GridPoint> points_;
  double alpha_;
  std::span<uint8_t> kept_;
  Side& side_;
  ExactFill& out_;
  Csr incident_;                        // per vertex, the Delaunay cells around it
  mutable std::vector<uint32_t> seen_;  // per vertex, the gathering that saw it last
  mutable uint32_t stamp_ = 0;
  std::vector<OpenFace> faces_;   // every face opened, by number
  std::vector<uint32_t> bucket_;  // per hash bucket, its chain's first face (kNoFace: none)
  std::vector<uint32_t> queue_;   // faces to visit, first opened first
  size_t head_ = 0;
  // 12.0's fit tests: per vertex, the fill cells at it (a list through
  // fill_next_, by slot 4 x cell + corner; kNoSlot ends it) and their count;
  // the work spent and the faces it is measured against.
  static constexpr uint32_t kNoSlot = UINT32_MAX;
  bool only_fitting_ = false;
  bool in_context_ = false;                      // 13.0
  bool flips_ = false;                           // 14.0
  bool closing_first_ = false;                   // 23.0
  EdgeCounts boundary_edges_;                    // 23.0
  std::vector<std::pair<int, uint32_t>> keyed_;  // 23.0: ApexSearch's candidates by the faces they close
  std::vector<uint32_t> ring_;                   // second_ring()'s first ring
  FitBudget budget_;
  std::vector<uint32_t> fill_at_, fill_next_, fill_count_;
  uint64_t fit_work_ = 0, faces_given_cells_ = 0;
  bool over_fit_budget_ = false;
  // The face whose cells face_cells_ holds (by faces_given_cells_), and
  // those cells' corners.
  uint64_t face_cells_for_ = 0;
  std::vector<std::array<GridPoint, 4>> face_cells_;
  std::array<AdaptiveBit, kFilledContexts> filled_;
  std::array<AdaptiveBit, kFlipContexts> flip_;
  std::array<RankModels, kRankModels> rank_;
  AdaptiveBit seed_;
};

}  // namespace dtm::exact_cells
