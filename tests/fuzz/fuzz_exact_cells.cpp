// The exact cell section (spec/FORMAT.md §3.10) on arbitrary bytes, below
// the layer checksum that keeps the stream targets from reaching it
// damaged: never a crash; a section that decodes gives cells that are
// positively oriented, with every face of the kept cells and the fill shared
// by at most two cells on opposite sides, no two cells overlapping, and the
// fill coded again as the
// input's cells decodes to the same cells.
//
// Input: byte 0: bit 0 the point set (fuzz_point_sets.h); bits 1-3 which
// Delaunay cells are kept (0: all; k: all but every cell whose index is 0
// mod k + 1); bits 4-5 the section's version (0: 12.0, the apexes ranked
// among the candidates that fit; 1: 11.0, among them all; 2 or 3: 13.0,
// 12.0's ranks with the filled bits in the context of the Delaunay cell
// across and an apex outside the candidates ranked in the second ring);
// bit 6 set: 14.0 (13.0's after a flag per 3-2 flip of the kept cells);
// bit 7 set: 23.0 (14.0's with the filled bits in the context of the
// boundary's edges too and the apexes ranked closing faces first); then the
// section.
#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <vector>

#include "codec/sections/exact_cell_coder.h"
#include "codec/sections/exact_cell_coder_shared.h"
#include "fuzz_check.h"
#include "fuzz_point_sets.h"
#include "mesh/delaunay.h"
#include "mesh/predicates.h"
#include "mesh/topology.h"

namespace {

struct Level {
  std::span<const dtm::GridPoint> points;
  dtm::TetMesh dt;
  std::vector<uint32_t> order;
};
const Level& level(bool random) {
  static const auto make = [](bool r) {
    Level l;
    l.points = fuzz_point_set(r);
    l.dt = dtm::delaunay_tetrahedralize(l.points).value();
    l.order = dtm::canonical_cell_order(l.dt.cells);
    return l;
  };
  static const Level block = make(false), cloud = make(true);
  return random ? cloud : block;
}

std::set<dtm::MeshCell> sorted_cells(const std::vector<dtm::MeshCell>& cells) {
  std::set<dtm::MeshCell> out;
  for (dtm::MeshCell c : cells) {
    std::sort(c.begin(), c.end());
    out.insert(c);
  }
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const Level& l = level(data[0] & 1);
  const unsigned skip = (data[0] >> 1) & 7;
  dtm::ApexRanks ranks = (data[0] >> 7) & 1   ? dtm::ApexRanks::kClosingFirst
                         : (data[0] >> 6) & 1 ? dtm::ApexRanks::kAfterFlips
                         : (data[0] >> 5) & 1 ? dtm::ApexRanks::kAmongFittingInContext
                         : (data[0] >> 4) & 1 ? dtm::ApexRanks::kAmongCandidates
                                              : dtm::ApexRanks::kAmongFitting;
  std::vector<uint8_t> kept(l.dt.cells.size(), 1);
  if (skip)
    for (size_t c = 0; c < kept.size(); c += skip + 1) kept[c] = 0;
  constexpr double kAlpha = 3.0;
  const std::vector<uint8_t> carved = kept;  // 14.0's flips take cells from kept
  dtm::ExactFill fill;
  const dtm::Status s = dtm::decode_exact_cells(std::span(data + 1, size - 1), l.dt, l.points, kAlpha, kept,
                                                l.order, ranks, fill);
  if (!s.ok()) {
    FUZZ_CHECK(s.code() == dtm::StatusCode::kCorrupt);
    return 0;
  }
  // Every cell positive, every face of the level in at most two cells, on
  // opposite sides (the outward faces of two cells sharing it are reversed).
  std::map<dtm::exact_cells::FaceKey, std::vector<std::array<uint32_t, 3>>> faces;
  const auto add = [&](const dtm::MeshCell& c) {
    FUZZ_CHECK(dtm::orientation(l.points[c[0]], l.points[c[1]], l.points[c[2]], l.points[c[3]]) > 0);
    for (int k = 0; k < 4; ++k) {
      const auto f = dtm::exact_cells::outward_face(c, k);
      faces[dtm::exact_cells::key_of(f)].push_back(f);
    }
  };
  for (size_t c = 0; c < kept.size(); ++c)
    if (kept[c]) add(l.dt.cells[c]);
  for (const auto& c : fill.cells) add(c);
  for (const auto& [key, sides] : faces) {
    FUZZ_CHECK(sides.size() <= 2);
    if (sides.size() == 2) FUZZ_CHECK(dtm::exact_cells::reversed(sides[0], sides[1]));
  }
  // No two cells overlap (every pair of a fill cell with another cell).
  const auto corners = [&](const dtm::MeshCell& c) {
    return std::array<dtm::GridPoint, 4>{l.points[c[0]], l.points[c[1]], l.points[c[2]], l.points[c[3]]};
  };
  for (size_t i = 0; i < fill.cells.size(); ++i) {
    for (size_t c = 0; c < kept.size(); ++c)
      if (kept[c]) FUZZ_CHECK(!dtm::interiors_meet(corners(fill.cells[i]), corners(l.dt.cells[c])));
    for (size_t j = i + 1; j < fill.cells.size(); ++j)
      FUZZ_CHECK(!dtm::interiors_meet(corners(fill.cells[i]), corners(fill.cells[j])));
  }
  // Coded again as the input's cells beside the carving's: the same cells,
  // the same flips.
  dtm::ExactFill again, back;
  std::vector<uint32_t> source;
  std::vector<uint8_t> encoded_kept = carved, decoded_kept = carved;
  const auto section = dtm::encode_exact_cells(l.dt, l.points, kAlpha, encoded_kept, l.order, fill.cells,
                                               ranks, again, source);
  FUZZ_CHECK(section.ok());
  FUZZ_CHECK(
      dtm::decode_exact_cells(*section, l.dt, l.points, kAlpha, decoded_kept, l.order, ranks, back).ok());
  FUZZ_CHECK(sorted_cells(back.cells) == sorted_cells(fill.cells));
  FUZZ_CHECK(encoded_kept == kept && decoded_kept == kept);
  return 0;
}
