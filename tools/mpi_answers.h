// What a rank of an MPI run does while it waits (tools/mpi_session.h):
// waiting for an exchange without spinning, and answering the other ranks'
// questions on a thread of its own while it works (RankAnswers,
// common/exchange.h). Included only where the build has MPI.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <exception>
#include <initializer_list>
#include <span>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "common/exchange.h"

namespace dtm {

// Sleeps between polls: 20 us at first, doubling up to 1 ms, so that a
// long wait costs about a thousand polls a second and a finished one is
// seen within a millisecond.
class Backoff {
 public:
  void pause() {
    std::this_thread::sleep_for(pause_);
    pause_ = std::min<std::chrono::microseconds>(2 * pause_, std::chrono::microseconds(1000));
  }

 private:
  std::chrono::microseconds pause_{20};
};

// Waits for a request without spinning. MPI's blocking calls poll the
// whole time (Open MPI yields the core only when oversubscribed), so a
// rank that has finished its blocks would take a core from the ranks
// still at work, and count it as its own CPU time. A short run of tests
// catches the exchanges that end at once; then the polls back off.
inline void wait_for(MPI_Request& request) {
  int done = 0;
  for (int spin = 0; spin < 64 && !done; ++spin) MPI_Test(&request, &done, MPI_STATUS_IGNORE);
  for (Backoff backoff; !done; MPI_Test(&request, &done, MPI_STATUS_IGNORE)) backoff.pause();
}

// RankAnswers on MPI (it needs MPI_THREAD_MULTIPLE): a thread of each rank
// waits for questions on a communicator of their own and sends back each
// answer. A question carries the tag its answer is to come back with, one
// per question this rank has out, so that several threads may ask at once.
class MpiAnswers final : public RankAnswers {
 public:
  MpiAnswers(MPI_Comm world, Answerer answer) : answer_(std::move(answer)) {
    MPI_Comm_dup(world, &comm_);
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    serving_ = std::thread([this] { serve(); });
  }
  ~MpiAnswers() override {
    // Every rank has asked all it will once every rank is here.
    MPI_Request request = MPI_REQUEST_NULL;
    MPI_Ibarrier(comm_, &request);
    wait_for(request);
    MPI_Send(nullptr, 0, MPI_BYTE, rank_, kStop, comm_);
    serving_.join();
    MPI_Comm_free(&comm_);
  }
  MpiAnswers(const MpiAnswers&) = delete;
  MpiAnswers& operator=(const MpiAnswers&) = delete;

  int rank() const override { return rank_; }

  std::vector<std::vector<uint8_t>> ask_others(std::span<const uint8_t> question) override {
    if (question.size() > static_cast<size_t>(INT32_MAX) - 4)
      throw std::runtime_error("MPI: a question over 2 GiB");
    const int32_t reply = kFirstReply + static_cast<int32_t>(next_reply_++ % kReplyTags);
    std::vector<uint8_t> sent(4 + question.size());
    std::memcpy(sent.data(), &reply, 4);
    if (!question.empty()) std::memcpy(sent.data() + 4, question.data(), question.size());
    std::vector<MPI_Request> sends;
    for (int r = 0; r < size_; ++r)
      if (r != rank_)
        MPI_Isend(sent.data(), static_cast<int>(sent.size()), MPI_BYTE, r, kAsk, comm_,
                  &sends.emplace_back());
    std::vector<std::vector<uint8_t>> answers(static_cast<size_t>(size_));
    for (int r = 0; r < size_; ++r)
      if (r != rank_) answers[static_cast<size_t>(r)] = receive({r}, reply).first;
    for (MPI_Request& s : sends) wait_for(s);
    return answers;
  }

 private:
  static constexpr int kStop = 1, kAsk = 2, kFirstReply = 16, kReplyTags = 16384;

  // The next message with `tag` from one of `sources` (MPI_ANY_SOURCE: any),
  // or with kStop when `or_stop`, waited for without spinning; and its
  // status.
  std::pair<std::vector<uint8_t>, MPI_Status> receive(std::initializer_list<int> sources, int tag,
                                                      bool or_stop = false) {
    MPI_Message message = MPI_MESSAGE_NULL;
    MPI_Status status;
    int found = 0;
    for (Backoff backoff;; backoff.pause()) {
      for (int source : sources) {
        if (or_stop) MPI_Improbe(source, kStop, comm_, &found, &message, &status);
        if (!found) MPI_Improbe(source, tag, comm_, &found, &message, &status);
        if (found) break;
      }
      if (found) break;
    }
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::vector<uint8_t> bytes(static_cast<size_t>(std::max(0, count)));
    MPI_Mrecv(bytes.data(), count, MPI_BYTE, &message, MPI_STATUS_IGNORE);
    return {std::move(bytes), status};
  }

  // Answers each question until this rank stops itself.
  void serve() {
    for (;;) {
      auto [question, status] = receive({MPI_ANY_SOURCE}, kAsk, true);
      if (status.MPI_TAG == kStop) return;
      int32_t reply = 0;
      if (question.size() < 4) continue;  // not this program's
      std::memcpy(&reply, question.data(), 4);
      std::vector<uint8_t> answer;
      try {
        answer = answer_(std::span<const uint8_t>(question).subspan(4));
      } catch (const std::exception&) {
        answer.clear();  // no answer: the asker fails (its answers are short)
      }
      MPI_Send(answer.data(), static_cast<int>(answer.size()), MPI_BYTE, status.MPI_SOURCE, reply, comm_);
    }
  }

  Answerer answer_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  std::atomic<uint32_t> next_reply_{0};
  std::thread serving_;
};

}  // namespace dtm
