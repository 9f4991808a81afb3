// The ranks of an MPI run, as threads of one test process: each thread
// makes a ThreadRanks::Rank and hands it to the library as its exchange.
#pragma once

#include <barrier>
#include <cstdint>
#include <span>
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

   private:
    ThreadRanks& all_;
    int rank_;
  };

 private:
  std::vector<std::vector<uint8_t>> slots_;
  std::barrier<> sync_;
};

}  // namespace dtm::test
