// Level 0 equal to the input's tetrahedra (format 11.0 and later, kFlagExact,
// spec/FORMAT.md §3.10; meshenc --exact), encoder and decoder side by side.
//
// A mesher's output is mostly Delaunay: the decoder's DT(V_0) already holds
// 88-99% of its cells. Level 0's carving section then keeps exactly the
// Delaunay cells that are input cells (any kept set can be coded there), and
// this section fills what they leave open with the input's other cells,
// grown face by face: every face of a kept cell with no kept cell across it
// is open, visited in a queue (the kept cells in canonical order, then the
// faces each new cell opens); an open face is either the mesh's boundary or
// has an input cell across it, whose fourth corner (the apex) is coded as
// its rank among the candidates near the face, ordered as the Delaunay
// criterion ranks them (the apex whose sphere through the face holds none of
// the others first). A mesher moves few points far from where Delaunay put
// them: the apex is most often rank 0. An apex that is not a candidate is
// sent by its index; a part of the mesh no open face reaches (no Delaunay
// cell in it) starts from a seed cell sent whole. From 14.0 the section
// starts with a flag per valid 3-2 flip of the kept cells: the commonest
// place a TetGen mesh leaves the Delaunay cells is one such flip (26-48% of
// the non-Delaunay cells of the corpus's TetGen models, research/
// exact_regions.md), whose three cells the carving then keeps and the flag
// trades for the input's two, where the carving and the fill spent 5-7 bits.
//
// The decoder checks every cell it adds: its corners exist and are distinct,
// it is positively oriented (its apex on the outer side of the face it
// grows from), each of its faces is either new, or closes an open face from
// the other side; a face never has three cells and no cell crosses a face
// declared the boundary. The fill ends when every open face is closed or the
// boundary. A hostile section is refused (kCorrupt) and never makes the
// decoder hold more than kMaxFillCellsPerVertex cells a vertex.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/grid.h"
#include "common/status.h"
#include "mesh/delaunay.h"

namespace dtm {

using MeshCell = std::array<uint32_t, 4>;

// The most fill cells a section may add, per vertex of the level (a mesh
// has about 6.5 cells a vertex, the Delaunay tetrahedralization's own cap is
// kMaxCellsPerVertex).
inline constexpr uint64_t kMaxFillCellsPerVertex = kMaxCellsPerVertex;

// What the fill adds to the kept Delaunay cells.
struct ExactFill {
  // Each positively oriented: corners 0-2 the face it grew from, seen from
  // outside it, corner 3 its apex (a seed: ascending, but for the last two
  // swapped when that would turn it inside out).
  std::vector<MeshCell> cells;
  // neighbours[i][k]: the cell across the face of cells[i] opposite corner k,
  // in the extended numbering (a Delaunay cell's index, dt.cells.size() + j
  // for fill cell j) or -1 (none: the mesh's boundary).
  std::vector<std::array<int32_t, 4>> neighbours;
  // Kept Delaunay cells whose face a fill cell now meets.
  struct Link {
    uint32_t cell = 0;
    uint8_t corner = 0;  // the corner the face does not have
    int32_t other = 0;   // the fill cell, extended numbering
  };
  std::vector<Link> links;
};

// How a section codes its symbols (spec/FORMAT.md §3.10), by the stream's
// version. 11.0 ranks an apex among all its candidates; 12.0 only among
// those whose cell with the face fits, its interior meeting no cell the
// fill has added at one of the face's corners (the apex itself always
// fits): both sides know those cells, and a candidate that does not fit
// cannot be the apex, so the ranks fall (the section by 26% on the corpus's
// sliver-heavy meshes). 13.0 ranks as 12.0 does, and also codes whether a
// face is filled in the context of the Delaunay cell across it (alpha's
// verdict, its shape, whether a neighbour of it is kept), and an apex that
// is not a candidate by its rank in the face's second ring before its
// index (bench/results/EXACT.md measures both; 13.0's level 0 carving
// contexts change too, carving_coder.h). 14.0 codes as 13.0 does after the
// flip flags (flip_context()). 23.0 (kClosingFirst) codes whether a face is
// filled in the context of how many faces declared the boundary its edges
// already have, and ranks an apex among the candidates that fit in another
// order: the first in the Delaunay order, then the others by how many open
// faces their cell would close, in the context of how many the first
// closes; a candidate whose cell would cross a face declared the boundary,
// or give a face a third cell, does not fit (ApexSearch,
// exact_cell_coder_shared.h).
enum class ApexRanks : uint8_t {
  kAmongCandidates,
  kAmongFitting,
  kAmongFittingInContext,
  kAfterFlips,
  kClosingFirst
};
inline ApexRanks apex_ranks_of(uint8_t format_major) {
  return format_major >= 23   ? ApexRanks::kClosingFirst
         : format_major >= 14 ? ApexRanks::kAfterFlips
         : format_major >= 13 ? ApexRanks::kAmongFittingInContext
         : format_major >= 12 ? ApexRanks::kAmongFitting
                              : ApexRanks::kAmongCandidates;
}
inline uint8_t format_major_of(ApexRanks ranks) {
  switch (ranks) {
    case ApexRanks::kClosingFirst:
      return 23;
    case ApexRanks::kAfterFlips:
      return 14;
    case ApexRanks::kAmongFittingInContext:
      return 13;
    case ApexRanks::kAmongFitting:
      return 12;
    case ApexRanks::kAmongCandidates:
      break;
  }
  return 11;
}

// 12.0's bound on the fit tests' work (spec/FORMAT.md §3.10): per face
// given a cell on average, plus a slack. The defaults are the format's;
// tests lower them to reach the refusal and the encoder's fall back.
struct FitBudget {
  uint64_t per_face = 1024;
  uint64_t slack = uint64_t{1} << 20;
};

// What a section spent (the encoder's report).
struct ExactStats {
  uint64_t open_faces = 0;       // faces given a symbol
  uint64_t fill_cells = 0;       // cells the fill added
  uint64_t rank_zero = 0;        // of them, with the first candidate as apex
  uint64_t escapes = 0;          // apex not among the candidates
  uint64_t second_ring = 0;      // 13.0: of those, ranked in the second ring
  uint64_t seeds = 0;            // cells sent whole
  uint64_t fit_work = 0;         // 12.0: the fit tests' work (spec/FORMAT.md §3.10), as a decoder counts it
  uint64_t flip_candidates = 0;  // 14.0: the flips given a flag
  uint64_t flips = 0;            // of them, made (2 fill cells each)
};

// Encoder. `dt`, `points`: level 0 in the decoder's numbering; `order`: dt's
// canonical cell order; `kept`: per cell of dt, nonzero when it is an input
// cell (14.0: and the Delaunay cells to flip, keep_flipped_cells()); on
// return, the cells the flips replaced are 0. `rest`: the input's other
// cells (any orientation). `ranks`: the ranks asked for; kAmongFitting and
// later fall back to kAmongCandidates (and say so in `ranks`; `kept` then
// without the cells 14.0's flips would have replaced, whose carving
// verdicts must change) where their tests would pass the budget a decoder
// allows.
// `fill` receives the cells as the decoder will make them, `source` per
// fill cell its index in `rest`. kInvalidInput, naming the problem, when
// the input is not a valid mesh on the grid (a flat or inverted cell, two
// cells on one side of a face, a face of three cells, cells that overlap).
StatusOr<std::vector<uint8_t>> encode_exact_cells(const TetMesh& dt, std::span<const GridPoint> points,
                                                  double alpha, std::span<uint8_t> kept,
                                                  std::span<const uint32_t> order,
                                                  std::span<const MeshCell> rest, ApexRanks& ranks,
                                                  ExactFill& fill, std::vector<uint32_t>& source,
                                                  ExactStats* stats = nullptr, const FitBudget& budget = {});

// 14.0's encoder: marks in `kept` (the carving's verdicts) the three cells
// around every edge of dt whose 3-2 flip makes two cells of `rest`, which
// the section's flags then trade for them. Returns how many flips.
uint64_t keep_flipped_cells(const TetMesh& dt, std::span<const GridPoint> points,
                            std::span<const MeshCell> rest, std::span<uint8_t> kept);

// Decoder: the fill the section describes, checked as the header says;
// `ranks` as the stream's version says (apex_ranks_of()); `kept` loses the
// cells 14.0's flips replace.
Status decode_exact_cells(std::span<const uint8_t> section, const TetMesh& dt,
                          std::span<const GridPoint> points, double alpha, std::span<uint8_t> kept,
                          std::span<const uint32_t> order, ApexRanks ranks, ExactFill& fill,
                          const FitBudget& budget = {});

// Level 0 as both sides then code its regions, faces and cell values: dt's
// cells followed by the fill's, every kept cell's neighbour across each face
// the cell that is there now. (A Delaunay cell the fill replaced keeps its
// old neighbours; it is not kept.)
void extend_with_fill(TetMesh& dt, const ExactFill& fill);

}  // namespace dtm
