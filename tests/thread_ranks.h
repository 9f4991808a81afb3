// The ranks of an MPI run, as threads of one test process: each thread
// makes a ThreadRanks::Rank and hands it to the library as its exchange.
#pragma once

#include <barrier>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <type_traits>
#include <vector>

#include "common/exchange.h"

namespace dtm::test {

class ThreadRanks {
 public:
  explicit ThreadRanks(int ranks) : slots_(static_cast<size_t>(ranks)), sync_(ranks) {}

  class Rank final : public RankExchange {
   public:
    Rank(ThreadRanks& all, int rank) : all_(all), rank_(rank) {}
    int rank() const override { return rank_; }
    int size() const override { return static_cast<int>(all_.slots_.size()); }
    std::vector<std::vector<uint8_t>> all_gather(std::span<const uint8_t> mine) override {
      all_.slots_[static_cast<size_t>(rank_)].assign(mine.begin(), mine.end());
      all_.sync_.arrive_and_wait();
      std::vector<std::vector<uint8_t>> out = all_.slots_;
      all_.sync_.arrive_and_wait();  // nobody writes again before everyone has read
      return out;
    }
    // Asked on the asking thread: each rank's answerer called there, once
    // every rank has set one (as MPI holds a question until the rank
    // answering it has started).
    std::unique_ptr<RankAnswers> answer_while_working(const Answerer& answer) override {
      if (!all_.answering_) return nullptr;
      return std::make_unique<Answers>(all_, rank_, answer);
    }

   private:
    ThreadRanks& all_;
    int rank_;
  };

  // Whether ranks answer while they work (answer_while_working()); when
  // not, they hear each other only in all_gather(), as on an MPI without
  // threads.
  void answer_while_working(bool on) { answering_ = on; }

 private:
  class Answers final : public RankAnswers {
   public:
    Answers(ThreadRanks& all, int rank, Answerer answer) : all_(all), rank_(rank) {
      const std::lock_guard lock(all_.mutex_);
      all_.answerers_.resize(all_.slots_.size());
      all_.answerers_[static_cast<size_t>(rank_)] = std::move(answer);
      all_.answerer_set_.notify_all();
    }
    ~Answers() override {
      all_.sync_.arrive_and_wait();  // nobody asks any more
      const std::lock_guard lock(all_.mutex_);
      all_.answerers_[static_cast<size_t>(rank_)] = nullptr;
    }
    Answers(const Answers&) = delete;
    Answers& operator=(const Answers&) = delete;
    int rank() const override { return rank_; }
    std::vector<std::vector<uint8_t>> ask_others(std::span<const uint8_t> question) override {
      std::vector<std::vector<uint8_t>> out(all_.slots_.size());
      for (size_t r = 0; r < out.size(); ++r) {
        if (static_cast<int>(r) == rank_) continue;
        Answerer answer;
        {
          std::unique_lock lock(all_.mutex_);
          all_.answerer_set_.wait(lock, [&] { return all_.answerers_.size() > r && all_.answerers_[r]; });
          answer = all_.answerers_[r];
        }
        out[r] = answer(question);
      }
      return out;
    }

   private:
    ThreadRanks& all_;
    int rank_;
  };

  std::vector<std::vector<uint8_t>> slots_;
  std::barrier<> sync_;
  bool answering_ = true;
  std::mutex mutex_;
  std::condition_variable answerer_set_;
  std::vector<Answerer> answerers_;
};

// Runs work(rank, r) on `ranks` threads, each given its rank's exchange
// (the ranks answering each other while they work, or only in their
// exchanges), and returns what each returned, in rank order.
template <class Work>
auto on_ranks(int ranks, bool answering, const Work& work) {
  using Result = std::invoke_result_t<const Work&, RankExchange&, int>;
  ThreadRanks all(ranks);
  all.answer_while_working(answering);
  std::vector<Result> out(static_cast<size_t>(ranks));
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r)
    threads.emplace_back([&, r] {
      ThreadRanks::Rank rank(all, r);
      out[static_cast<size_t>(r)] = work(rank, r);
    });
  for (auto& t : threads) t.join();
  return out;
}

}  // namespace dtm::test
