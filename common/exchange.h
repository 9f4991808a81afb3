// What the ranks of a run share, for the work that is split among processes
// (meshenc under mpirun: codec/blocks/bricked_encoder.h). The libraries never call
// MPI themselves: the tools hand them an exchange (tools/mpi_session.h), and
// a run in one process hands them SingleProcess. One operation is enough:
// every rank gives its bytes and receives every rank's, in rank order; each
// rank then merges the results in an order that does not depend on which
// rank made them, so that the outcome is the same for any number of ranks.
// Where the exchange can, a rank may also ask the others a question while
// they work (RankAnswers), answered by a thread of theirs, so that work
// that needs another rank's data goes on instead of waiting for the next
// exchange.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "common/status.h"
#include "common/threads.h"

namespace dtm {

// Questions to the other ranks of a run, answered while they work.
class RankAnswers {
 public:
  virtual ~RankAnswers() = default;
  virtual int rank() const = 0;
  // Every rank's answer to `question`, in rank order, this rank's own left
  // empty. Safe to call from several threads at once.
  virtual std::vector<std::vector<uint8_t>> ask_others(std::span<const uint8_t> question) = 0;
};

// How a rank answers: called on a thread of its own, beside the rank's
// work (so it must only read what the work does not change).
using Answerer = std::function<std::vector<uint8_t>(std::span<const uint8_t> question)>;

class RankExchange {
 public:
  virtual ~RankExchange() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every rank's bytes, in rank order (the same on every rank). Every rank
  // must call it, the same number of times.
  virtual std::vector<std::vector<uint8_t>> all_gather(std::span<const uint8_t> mine) = 0;
  // Answers the other ranks' questions with `answer` from now until the
  // returned object is destroyed, and asks theirs through it; nullptr
  // where this exchange cannot (then a rank hears the others only in
  // all_gather()). Every rank must call it, and destroy what it returned,
  // at the same step of the work: the destructor waits until every rank
  // has come to its own, after which nobody asks.
  virtual std::unique_ptr<RankAnswers> answer_while_working(const Answerer& answer) {
    (void)answer;
    return nullptr;
  }
  // The threads this rank's work may use while only the ranks marked in
  // `busy` (one byte per rank) have work: where ranks share a machine's
  // cores, a rank at work may take those of ranks that only wait.
  virtual int threads_while_busy(std::span<const uint8_t> busy) const {
    (void)busy;
    return thread_count();
  }
};

// Every rank's `mine` shared: the first refusal in rank order, on every rank
// (or Ok where none refused). A check of a rank's own input is agreed on
// before the next exchange: a rank that returned alone would leave the others
// waiting in it. Every rank must call it at the same step.
inline Status agreed(RankExchange& exchange, const Status& mine) {
  std::vector<uint8_t> bytes;
  if (!mine.ok()) {
    bytes.push_back(static_cast<uint8_t>(mine.code()));
    bytes.insert(bytes.end(), mine.message().begin(), mine.message().end());
  }
  for (const auto& theirs : exchange.all_gather(bytes))
    if (!theirs.empty())
      return Status{static_cast<StatusCode>(theirs[0]), std::string(theirs.begin() + 1, theirs.end())};
  return Status::Ok();
}

// One process: rank 0 of 1.
class SingleProcess final : public RankExchange {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::vector<std::vector<uint8_t>> all_gather(std::span<const uint8_t> mine) override {
    return {std::vector<uint8_t>(mine.begin(), mine.end())};
  }
};

}  // namespace dtm
