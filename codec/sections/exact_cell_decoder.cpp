// The exact cell coder's decoder (spec/FORMAT.md §3.10); exact_cell_encoder.cpp
// mirrors it, exact_cell_coder_shared.h holds the fill both make.
#include <algorithm>

#include "codec/sections/exact_cell_coder.h"
#include "codec/sections/exact_cell_coder_shared.h"

namespace dtm {
namespace exact_cells {
namespace {

class Decoder {
 public:
  Decoder(std::span<const uint8_t> section, std::span<const GridPoint> points)
      : rc_(section), points_(points) {}

  // A section that runs past its end only reads zeros: stop at once.
  Status check() const { return rc_.overran() ? corrupt("the section ends early") : Status::Ok(); }

  bool filled(AdaptiveBit& model, const OpenFace&) { return rc_.decode(model); }

  template <class Fit, class Ring>
  Status apex(const OpenFace&, std::vector<uint32_t>& candidates, const ApexOrder& less, RankModels& models,
              const Fit& fit, const Ring& ring, uint32_t& apex) {
    uint64_t rank = 0;
    DTM_RETURN_IF_ERROR(get_rank(rc_, models, rank));
    if (rank > candidates.size()) return corrupt("an apex rank past the candidates");
    if (fit.on()) return fitting_apex(candidates, less, fit, ring, rank, apex);
    if (rank == candidates.size()) return escaped(ring, less, apex);
    // Rank 0, the Delaunay-like apex, is most of them: one pass finds it.
    if (rank == 0) {
      apex = *std::min_element(candidates.begin(), candidates.end(), less);
      return Status::Ok();
    }
    const auto at = candidates.begin() + static_cast<std::ptrdiff_t>(rank);
    std::nth_element(candidates.begin(), at, candidates.end(), less);
    apex = *at;
    return Status::Ok();
  }

  // 23.0: the rank-th candidate that fits in the search's order; one past
  // the last, an escape.
  template <class Search, class Ring>
  Status ranked_apex(const OpenFace&, Search& search, const Ring& ring, uint32_t& apex) {
    uint32_t q = 0;
    bool found = false;
    DTM_RETURN_IF_ERROR(search.next(q, found));
    uint64_t rank = 0;
    DTM_RETURN_IF_ERROR(get_rank(rc_, search.models(), rank));
    uint64_t seen = found;  // the candidates found to fit, q the last
    while (found && seen <= rank) {
      DTM_RETURN_IF_ERROR(search.next(q, found));
      seen += found;
    }
    if (found) {
      apex = q;
      return Status::Ok();
    }
    // None left: the rank must be one past the last.
    if (rank != seen) return corrupt("an apex rank past the candidates that fit");
    return escaped(ring, search.less(), apex);
  }

  bool another_seed(AdaptiveBit& model) { return rc_.decode(model); }

  bool flipped(AdaptiveBit& model, const FlipCandidate&) { return rc_.decode(model); }

  // 12.0: the candidates in their order, tested until the rank-th that
  // fits; one past the last that fits, an index. Most apexes are the
  // first candidate that fits: picking the next in order costs a pass,
  // and past a few the rest are sorted at once.
  template <class Fit, class Ring>
  Status fitting_apex(std::vector<uint32_t>& candidates, const ApexOrder& less, const Fit& fit,
                      const Ring& ring, uint64_t rank, uint32_t& apex) {
    constexpr size_t kPicks = 8;
    uint64_t fitting = 0;
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (i < kPicks) {
        std::iter_swap(
            candidates.begin() + static_cast<std::ptrdiff_t>(i),
            std::min_element(candidates.begin() + static_cast<std::ptrdiff_t>(i), candidates.end(), less));
      } else if (i == kPicks) {
        std::sort(candidates.begin() + static_cast<std::ptrdiff_t>(i), candidates.end(), less);
      }
      bool fits = false;
      DTM_RETURN_IF_ERROR(fit(candidates[i], fits));
      if (!fits) continue;
      if (fitting == rank) {
        apex = candidates[i];
        return Status::Ok();
      }
      ++fitting;
    }
    if (rank > fitting) return corrupt("an apex rank past the candidates that fit");
    return escaped(ring, less, apex);
  }

  // An apex that is not a candidate: in 13.0 its rank in the second ring,
  // one past the ring's end for its index; before, its index.
  template <class Ring>
  Status escaped(const Ring& ring, const ApexOrder& less, uint32_t& apex) {
    if (ring.on()) {
      DTM_RETURN_IF_ERROR(ring(second_));
      uint64_t rank = 0;
      DTM_RETURN_IF_ERROR(get_rank(rc_, ring.models(), rank));
      if (rank > second_.size()) return corrupt("an apex rank past the second ring");
      if (rank < second_.size()) {
        const auto at = second_.begin() + static_cast<std::ptrdiff_t>(rank);
        std::nth_element(second_.begin(), at, second_.end(), less);
        apex = *at;
        return Status::Ok();
      }
    }
    uint64_t v = 0;
    DTM_RETURN_IF_ERROR(rc_.decode_index(points_.size(), v));
    apex = static_cast<uint32_t>(v);
    return Status::Ok();
  }

  Status seed(MeshCell& cell) {
    for (uint32_t& v : cell) {
      uint64_t i = 0;
      DTM_RETURN_IF_ERROR(rc_.decode_index(points_.size(), i));
      v = static_cast<uint32_t>(i);
    }
    return Status::Ok();
  }

  void added(const MeshCell&) {}

  Status finish() const {
    if (!rc_.finished_cleanly())
      return corrupt(rc_.overran() ? "the section ends early"
                                   : "the section does not end where its bytes do");
    return Status::Ok();
  }

 private:
  RangeDecoder rc_;
  std::span<const GridPoint> points_;
  std::vector<uint32_t> second_;  // a face's second ring
};

}  // namespace
}  // namespace exact_cells

Status decode_exact_cells(std::span<const uint8_t> section, const TetMesh& dt,
                          std::span<const GridPoint> points, double alpha, std::span<uint8_t> kept,
                          std::span<const uint32_t> order, ApexRanks ranks, ExactFill& fill,
                          const FitBudget& budget) {
  if (kept.size() != dt.cells.size()) return exact_cells::corrupt("the carving is not the level's");
  exact_cells::Decoder side(section, points);
  exact_cells::Fill<exact_cells::Decoder> walk(dt, points, alpha, kept, side, fill, ranks, budget);
  Status s = walk.run(order);
  if (!s.ok()) {
    fill = {};
    return s;
  }
  return side.finish();
}

void extend_with_fill(TetMesh& dt, const ExactFill& fill) {
  dt.cells.insert(dt.cells.end(), fill.cells.begin(), fill.cells.end());
  dt.neighbors.insert(dt.neighbors.end(), fill.neighbours.begin(), fill.neighbours.end());
  for (const ExactFill::Link& l : fill.links) dt.neighbors[l.cell][l.corner] = l.other;
}

}  // namespace dtm
