#include "codec/blocks/reference_questions.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace dtm {

int ReferenceParts::answer4(const Point4& p) const {
  for (size_t r = 0; r < regions.size(); ++r) {
    if (!regions[r]) continue;
    switch (regions[r]->answer4(p)) {
      case ReferenceSolid::Answer::kInside:
        return static_cast<int>(r + 1);
      case ReferenceSolid::Answer::kOutside:
        continue;
      case ReferenceSolid::Answer::kUnknown:
        // (A higher region's answer would not do: this one may hold p.)
        return -1;
    }
  }
  return 0;
}

uint8_t ReferenceParts::region_here4(const Point4& p) const {
  // A region holds p when one rank knows it does or holds a cell holding
  // it (a part that knows is right; one that does not holds no such cell
  // unless the whole's region holds p).
  for (size_t r = 0; r < regions.size(); ++r) {
    if (!regions[r]) continue;
    const ReferenceSolid::Answer a = regions[r]->answer4(p);
    if (a == ReferenceSolid::Answer::kInside ||
        (a == ReferenceSolid::Answer::kUnknown && regions[r]->holds4(p)))
      return static_cast<uint8_t>(r + 1);
  }
  return 0;
}

int AnswerBook::find(const Point4& p) const {
  const auto it = std::lower_bound(answers_.begin(), answers_.end(), p,
                                   [](const auto& a, const Point4& q) { return a.first < q; });
  return it != answers_.end() && it->first == p ? it->second : -1;
}

void AnswerBook::add(std::span<const Point4> points, std::span<const uint8_t> regions) {
  const size_t before = answers_.size();
  for (size_t i = 0; i < points.size(); ++i) answers_.emplace_back(points[i], regions[i]);
  std::inplace_merge(answers_.begin(), answers_.begin() + static_cast<std::ptrdiff_t>(before),
                     answers_.end());
}

uint8_t AskingSolid::region_point4(const std::array<int64_t, 3>& p) const {
  const int here = parts_.answer4(p);
  if (here >= 0) return static_cast<uint8_t>(here);
  int known = book_.find(p);
  if (known < 0) known = asked_.find(p);
  if (known >= 0) return static_cast<uint8_t>(known);
  const std::lock_guard<std::mutex> lock(mutex_);
  questions_.push_back(p);
  return 0;
}

Status AskingSolid::settle() const {
  if (!asked()) return Status::Ok();
  return {StatusCode::kNeedMoreInput, "the reference's answers are asked of the ranks"};
}

std::vector<AnswerBook::Point4> AskingSolid::questions() const {
  std::vector<AnswerBook::Point4> q = questions_;
  std::sort(q.begin(), q.end());
  q.erase(std::unique(q.begin(), q.end()), q.end());
  return q;
}

namespace {

// A block's bytes in a round: done with its result, or its questions.
constexpr uint8_t kDone = 1, kAsked = 2, kSkipped = 0;

void put_points(ByteWriter& w, std::span<const AnswerBook::Point4> points) {
  w.u64(points.size());
  for (const auto& p : points)
    for (int64_t c : p) w.u64(static_cast<uint64_t>(c));
}

std::vector<AnswerBook::Point4> get_points(BlockReader& r) {
  std::vector<AnswerBook::Point4> points(r.u64());
  for (auto& p : points)
    for (int64_t& c : p) c = static_cast<int64_t>(r.u64());
  return points;
}

// A byte per point: the lowest region this rank finds holding it.
std::vector<uint8_t> regions_here(const ReferenceParts& parts, std::span<const AnswerBook::Point4> points) {
  std::vector<uint8_t> regions(points.size(), 0);
  for (size_t i = 0; i < points.size(); ++i) regions[i] = parts.region_here4(points[i]);
  return regions;
}

// Every rank's answers (of `n` points) together: per point the least
// nonzero region, 0 where no rank found one.
std::vector<uint8_t> least_regions(std::span<const std::vector<uint8_t>> ranks, size_t n) {
  std::vector<uint8_t> least(n, 0);
  for (const std::vector<uint8_t>& regions : ranks) {
    if (regions.size() < n) throw std::runtime_error("a rank's answers are short");
    for (size_t i = 0; i < n; ++i)
      if (regions[i] != 0 && (least[i] == 0 || regions[i] < least[i])) least[i] = regions[i];
  }
  return least;
}

}  // namespace

std::vector<uint8_t> answer_questions(const ReferenceParts& parts, std::span<const uint8_t> question) {
  BlockReader r(question);
  return regions_here(parts, get_points(r));
}

bool AskingSolid::ask() const {
  if (!ranks_ || questions_.empty()) return false;
  const std::vector<AnswerBook::Point4> q = questions();
  ByteWriter w;
  put_points(w, q);
  const std::vector<uint8_t> question = w.take();
  // The others' answers, and this rank's own in its place.
  std::vector<std::vector<uint8_t>> answers = ranks_->ask_others(question);
  answers.at(static_cast<size_t>(ranks_->rank())) = regions_here(parts_, q);
  asked_.add(q, least_regions(answers, q.size()));
  answered_ += q.size();
  questions_.clear();
  return true;
}

std::vector<std::vector<uint8_t>> run_blocks_asking(
    const BlockPlan& plan, RankExchange& exchange, const ReferenceParts& parts, AnswerBook& book,
    RankAnswers* ranks, const std::function<StatusOr<std::vector<uint8_t>>(size_t, const Solid&)>& work,
    Status& status, QuestionCount& count, int at_once) {
  std::vector<std::vector<uint8_t>> out(plan.blocks.size());
  std::vector<uint8_t> done(plan.blocks.size(), 0);
  // Each round settles at least the next question of every block's work
  // (its answers before it are right): a block asks at most once a stage of
  // its work, and its stages are bounded (repair rounds); this is a guard.
  constexpr int kMostRounds = 200;
  for (int round = 0;; ++round) {
    if (round >= kMostRounds) {
      status = {StatusCode::kInternal, "the reference's questions did not settle"};
      return out;
    }
    const auto results = run_blocks(
        plan, exchange,
        [&](size_t k) -> StatusOr<std::vector<uint8_t>> {
          ByteWriter w;
          if (done[k]) {
            w.u8(kSkipped);
            return w.take();
          }
          AskingSolid asking(parts, book, ranks);
          StatusOr<std::vector<uint8_t>> result = work(k, asking);
          // Work that asked ran on guesses: whatever it made (or the status
          // its settle() ended it with) is dropped.
          if (asking.asked()) {
            w.u8(kAsked);
            w.u64(asking.answered());
            put_points(w, asking.questions());
            return w.take();
          }
          DTM_RETURN_IF_ERROR(result.status());
          w.u8(kDone);
          w.u64(asking.answered());
          put(w, std::span<const uint8_t>(*result));
          return w.take();
        },
        status, at_once);
    if (!status.ok()) return out;
    // Every rank has every block's bytes: the questions, all of them.
    std::vector<AnswerBook::Point4> asked;
    std::vector<size_t> first(plan.blocks.size() + 1, 0);
    for (size_t k = 0; k < results.size(); ++k) {
      first[k] = asked.size();
      BlockReader r(results[k]);
      const uint8_t kind = r.u8();
      if (kind != kSkipped) count.answered_at_once += r.u64();
      if (kind == kDone) {
        out[k] = r.bytes();
        done[k] = 1;
      } else if (kind == kAsked) {
        const std::vector<AnswerBook::Point4> q = get_points(r);
        asked.insert(asked.end(), q.begin(), q.end());
        ++count.runs;
      }
    }
    first.back() = asked.size();
    if (asked.empty()) return out;
    count.questions += asked.size();
    // Each rank: the lowest region it finds holding each point; the least.
    const std::vector<uint8_t> region =
        least_regions(exchange.all_gather(regions_here(parts, asked)), asked.size());
    // This rank keeps the answers to its own blocks' questions.
    std::vector<std::pair<AnswerBook::Point4, uint8_t>> mine;
    for (size_t k = 0; k < plan.blocks.size(); ++k)
      if (plan.rank[k] == exchange.rank())
        for (size_t i = first[k]; i < first[k + 1]; ++i) mine.emplace_back(asked[i], region[i]);
    std::sort(mine.begin(), mine.end());
    mine.erase(std::unique(mine.begin(), mine.end(),
                           [](const auto& a, const auto& b) { return a.first == b.first; }),
               mine.end());
    std::vector<AnswerBook::Point4> points;
    std::vector<uint8_t> answers;
    for (const auto& [p, a] : mine)
      if (book.find(p) < 0) points.push_back(p), answers.push_back(a);
    book.add(points, answers);
  }
}

}  // namespace dtm
