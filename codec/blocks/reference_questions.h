// The reference in parts on the ranks of a run (core/reference_solid.h):
// no rank holds every cell near the boundary, so a block's work may ask
// whether a point is in the solid where its rank's part does not know. The
// work is then run again once the ranks have answered every such question
// (each rank whether its own cells hold the point, OR-ed), until it asks
// nothing: its result is then the one the whole reference gives, on any
// number of ranks.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <vector>

#include "codec/blocks/block_runs.h"
#include "core/reference_solid.h"

namespace dtm {

// The answers the ranks gave, by point (at four times the grid's scale).
class AnswerBook {
 public:
  using Point4 = std::array<int64_t, 3>;
  // 1 inside, 0 outside, -1 not asked yet.
  int find(const Point4& p) const;
  // Adds answers (points ascending and not in the book).
  void add(std::span<const Point4> points, std::span<const uint8_t> inside);

 private:
  std::vector<std::pair<Point4, uint8_t>> answers_;  // ascending
};

// A part of the reference as one block's work sees it: what the part knows,
// then what the book says; a point neither knows is noted as a question and
// called outside, and the work ends at its next settle(), which returns a
// status that is not ok (its result would be thrown away).
class AskingSolid final : public Solid {
 public:
  AskingSolid(const ReferenceSolid& part, const AnswerBook& book) : part_(part), book_(book) {}
  bool contains_point4(const std::array<int64_t, 3>& p) const override;
  // kNeedMoreInput when there are questions: the rest of the work would run
  // on guesses.
  Status settle() const override;
  bool asked() const { return !questions_.empty(); }
  // The questions, ascending, each once.
  std::vector<AnswerBook::Point4> questions() const;

 private:
  const ReferenceSolid& part_;
  const AnswerBook& book_;
  mutable std::mutex mutex_;
  mutable std::vector<AnswerBook::Point4> questions_;
};

// What run_blocks_asking() asked, added up over its calls (the same on
// every rank).
struct QuestionCount {
  uint64_t questions = 0;  // points the ranks answered together
  uint64_t runs = 0;       // blocks' runs that asked them (each run again)
};
// run_blocks() of work carving to `part` (the solid it is handed), each
// block run again until it asks nothing; `book` keeps what was answered.
// Every rank must call it with the same plan. `at_once`: run_blocks'.
std::vector<std::vector<uint8_t>> run_blocks_asking(
    const BlockPlan& plan, RankExchange& exchange, const ReferenceSolid& part, AnswerBook& book,
    const std::function<StatusOr<std::vector<uint8_t>>(size_t, const Solid&)>& work, Status& status,
    QuestionCount& count, int at_once = 1);

}  // namespace dtm
