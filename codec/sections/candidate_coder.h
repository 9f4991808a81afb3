// Format 7.0's candidate section (spec/FORMAT.md §3.4), encoder and decoder
// side by side: a layer's new points sent as "beside this place", where the
// places are computed from the coarser level, which the decoder holds before
// the layer arrives.
//
// Quality mesh generators put their Steiner points at the circumcentres of
// the cells they refine (TetGen, CGAL's Mesh_3, gmsh's Delaunay) and split
// encroached edges at their midpoints; many of those cells and edges survive
// into the coarser level's Delaunay tetrahedralization. On the TetGen corpus,
// 16-22% of the finest layer's new points lie within one grid step of a
// circumcentre of the next level's cells, and on bunny_100k 6-11% of every
// layer's near an edge midpoint (research/circumcentre_candidates,
// research/point_models.md §4). Such a point costs a flag and a
// 27-way offset here (~9 bits) instead of ~28 in the set coder.
//
// The candidates: every finite cell's circumcentre and every edge's midpoint
// of DT(V_{l+1}), rounded to the grid exactly (integer arithmetic), in
// Morton order, distinct, none at a known point. Each gets an adaptive flag
// (is a new point within one grid step of it, per axis), and a hit the
// offset of that point. The layer's other points go to the set coder
// (spec §3.1), the hits known to it like the coarser levels' points.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "codec/stream/layer_coder.h"
#include "common/grid.h"
#include "common/status.h"

namespace dtm {

// The layer header's candidate_kinds bits.
inline constexpr uint8_t kCandidateCellCentres = 1;
inline constexpr uint8_t kCandidateEdgeMidpoints = 2;
inline constexpr uint8_t kKnownCandidateKinds = kCandidateCellCentres | kCandidateEdgeMidpoints;

// A cell gives a circumcentre only when its vertices span less than this on
// every axis (grid steps): the exact arithmetic then fits in 64 bits, and a
// larger cell is no place a refinement puts a point.
inline constexpr int32_t kMaxCandidateCellExtent = 1 << 13;

// Candidates are used on grids of at most 19 bits: a candidate is then one
// 64-bit key, its Morton code over its context's 5 bits.
inline constexpr int kMaxCandidateQBits = 19;

// Flag contexts: a circumcentre's by the rounded centre's squared distance
// to the cell's nearest vertex against the cell's shortest squared edge (bit
// widths, 12 classes); an edge midpoint's by the edge's squared length
// against the shorter of its ends' shortest squared edges (8 classes).
inline constexpr int kCentreContexts = 12;
inline constexpr int kMidpointContexts = 8;
inline constexpr int kCandidateContexts = kCentreContexts + kMidpointContexts;
inline constexpr int kCandidateContextBits = 5;

// A layer's candidates in ascending Morton order, distinct, none at a known
// point: one key each, (Morton code << 5) | context.
struct CandidateList {
  int qbits = 0;
  std::vector<uint64_t> keys;

  size_t size() const { return keys.size(); }
  bool empty() const { return keys.empty(); }
  uint64_t code(size_t i) const { return keys[i] >> kCandidateContextBits; }
  int context(size_t i) const { return static_cast<int>(keys[i] & ((1u << kCandidateContextBits) - 1)); }
  GridPoint at(size_t i) const { return morton_decode(code(i), qbits); }
};

// The candidates of a layer whose coarser level has the points `coarse`
// (vertex i is coarse[i]; `known` their ascending Morton codes) and the
// finite Delaunay cells `cells` (vertex ids, any order and orientation):
// those of `kinds`, inside the grid; of several at one place, the smallest
// context's. qbits <= kMaxCandidateQBits.
CandidateList layer_candidates(std::span<const std::array<uint32_t, 4>> cells,
                               std::span<const GridPoint> coarse, std::span<const MortonCode> known,
                               int qbits, uint8_t kinds);

// The section for the layer's new points `points`: which candidates have a
// new point beside them, and where. `sent[i]` is set for each point the
// section sends (each at most once); the rest go to the set coder.
std::vector<uint8_t> encode_candidate_section(const CandidateList& candidates,
                                              std::span<const GridPoint> points, std::vector<uint8_t>& sent);

// The same in two steps, for an encoder that tries several lists: every
// (candidate, offset, point) with the point within one step of the
// candidate on each axis (offset (dx + 1) + 3 (dy + 1) + 9 (dz + 1)),
// ascending; then the section from them (each candidate in turn takes its
// first point not taken).
struct CandidateHit {
  uint32_t candidate;
  uint8_t offset;
  uint32_t point;
  auto operator<=>(const CandidateHit&) const = default;  // NOLINT(modernize-use-nullptr): clang-tidy 14 bug
};
std::vector<CandidateHit> points_beside(const CandidateList& candidates, std::span<const GridPoint> points);
std::vector<uint8_t> encode_candidate_section(const CandidateList& candidates,
                                              std::span<const CandidateHit> beside, size_t point_count,
                                              std::vector<uint8_t>& sent);

// The points the section sends, appended to `out` in candidate order.
// kCorrupt if the section does not decode to at most `max_points` points
// inside the grid, or does not end where its bytes do. Whether they repeat
// a known point or each other is the caller's check (it knows the rest).
Status decode_candidate_section(std::span<const uint8_t> section, const CandidateList& candidates,
                                uint32_t max_points, std::vector<GridPoint>& out);

}  // namespace dtm
