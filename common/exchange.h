// What the ranks of a run share, for the work that is split among processes
// (meshenc under mpirun: codec/blocks/bricked_encoder.h). The libraries never call
// MPI themselves: the tools hand them an exchange (tools/mpi_session.h), and
// a run in one process hands them SingleProcess. One operation is enough:
// every rank gives its bytes and receives every rank's, in rank order; each
// rank then merges the results in an order that does not depend on which
// rank made them, so that the outcome is the same for any number of ranks.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace dtm {

class RankExchange {
 public:
  virtual ~RankExchange() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every rank's bytes, in rank order (the same on every rank). Every rank
  // must call it, the same number of times.
  virtual std::vector<std::vector<uint8_t>> all_gather(std::span<const uint8_t> mine) = 0;
};

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
