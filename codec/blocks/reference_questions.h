// The reference in parts on the ranks of a run (core/reference_solid.h):
// no rank holds every cell near the boundary, so a block's work may ask
// which region holds a point (0: none; one region without regions) where
// its rank's parts do not know. Where the ranks answer while they work
// (RankAnswers), the work asks them after each pass of questions and runs
// that pass again with the answers (settled_pass(), core/solid.h). Else the
// work is run again once the ranks have answered every such question in
// their next exchange (each rank the lowest region its own cells hold the
// point in, the least over the ranks), until it asks nothing. Either way
// its result is the one the whole reference gives, on any number of ranks.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "codec/blocks/block_runs.h"
#include "core/reference_solid.h"

namespace dtm {

// A rank's parts of the reference: one, or with regions one a region (each
// of that region's cells near its boundary, as core/region_solid.h holds a
// region whole), by region index; a region no rank has cells of has none.
struct ReferenceParts {
  using Point4 = std::array<int64_t, 3>;
  std::vector<std::optional<ReferenceSolid>> regions;

  // The region holding p (1 + its index, 0 outside), as the whole would
  // say (the lowest whose cells hold it), where these parts know; else -1.
  int answer4(const Point4& p) const;
  // The lowest region that holds p as far as this rank knows (its parts'
  // answers, and where they do not know, its own cells), 0 for none: the
  // least of the ranks' nonzero answers is the whole's.
  uint8_t region_here4(const Point4& p) const;
};

// The answers the ranks gave, by point (at four times the grid's scale).
class AnswerBook {
 public:
  using Point4 = std::array<int64_t, 3>;
  // The region holding the point (0 outside), -1 not asked yet.
  int find(const Point4& p) const;
  // Adds answers (points ascending and not in the book).
  void add(std::span<const Point4> points, std::span<const uint8_t> regions);

 private:
  std::vector<std::pair<Point4, uint8_t>> answers_;  // ascending
};

// The reference's parts as one block's work sees them: what the parts know,
// then what the books say; a point none knows is noted as a question and
// called outside. With `ranks`, ask() gets the answers and the work's pass
// runs again; without, the work ends at its next settle(), which returns a
// status that is not ok (its result would be thrown away).
class AskingSolid final : public Solid {
 public:
  AskingSolid(const ReferenceParts& parts, const AnswerBook& book, RankAnswers* ranks)
      : parts_(parts), book_(book), ranks_(ranks) {}
  bool contains_point4(const std::array<int64_t, 3>& p) const override { return region_point4(p) != 0; }
  uint8_t region_point4(const std::array<int64_t, 3>& p) const override;
  // kNeedMoreInput when there are questions: the rest of the work would run
  // on guesses.
  Status settle() const override;
  bool ask() const override;
  bool asked() const { return !questions_.empty(); }
  // The questions, ascending, each once.
  std::vector<AnswerBook::Point4> questions() const;
  // How many points ask() had answered.
  uint64_t answered() const { return answered_; }

 private:
  const ReferenceParts& parts_;
  const AnswerBook& book_;
  RankAnswers* ranks_;
  mutable AnswerBook asked_;  // what ask() had answered (added between passes)
  mutable uint64_t answered_ = 0;
  mutable std::mutex mutex_;
  mutable std::vector<AnswerBook::Point4> questions_;
};

// A rank's answer to a question of the points in `question` (put by
// AskingSolid::ask()): per point, ReferenceParts::region_here4().
std::vector<uint8_t> answer_questions(const ReferenceParts& parts, std::span<const uint8_t> question);

// What run_blocks_asking() asked, added up over its calls (the same on
// every rank).
struct QuestionCount {
  uint64_t questions = 0;         // points the ranks answered in their exchanges
  uint64_t runs = 0;              // blocks' runs that asked them (each run again)
  uint64_t answered_at_once = 0;  // points the ranks answered while they worked
};
// run_blocks() of work carving to `parts` (the solid it is handed), asking
// `ranks` (when not null) at once, else each block run again until it asks
// nothing; `book` keeps what was answered in the exchanges. Every rank must
// call it with the same plan. `at_once`: run_blocks'.
std::vector<std::vector<uint8_t>> run_blocks_asking(
    const BlockPlan& plan, RankExchange& exchange, const ReferenceParts& parts, AnswerBook& book,
    RankAnswers* ranks, const std::function<StatusOr<std::vector<uint8_t>>(size_t, const Solid&)>& work,
    Status& status, QuestionCount& count, int at_once = 1);

}  // namespace dtm
