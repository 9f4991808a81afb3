// What a tool shows of its long work on standard error: on a terminal, one
// status line rewritten in place ("[ 12.3 s] level 2: measuring the shape");
// with --verbose, a line per finished phase with how long it took, how many
// cores it kept busy on average (the process's CPU time over the wall time:
// where a phase leaves cores idle) and the memory in use after it (now and
// at the peak so far: for seeing where time and memory go); nothing when
// piped or quiet.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>
#include <string_view>
#include <utility>

namespace dtm {

class PhaseDisplay {
 public:
  // `live`: rewrite a status line (stderr is a terminal and not quiet);
  // `timings`: print every finished phase's duration; `prefix` begins each
  // of those lines (under mpirun, the rank's: every rank prints its own).
  PhaseDisplay(bool live, bool timings, std::string prefix = {})
      : live_(live), timings_(timings), prefix_(std::move(prefix)) {}
  ~PhaseDisplay() { finish(); }

  // A new phase starts; the one before it ends.
  void start(std::string_view phase);
  // Clears the status line, so that other output can be printed; the next
  // start() draws it again.
  void clear();
  // Ends the last phase (and, with timings, prints the total).
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  void end_current();
  static double cpu_seconds();  // the process's user + system time so far
  static double cores_busy(Clock::time_point since, double cpu_since);

  bool live_, timings_;
  std::string prefix_;
  bool drawn_ = false, finished_ = false;
  std::string current_;
  Clock::time_point begin_ = Clock::now(), phase_begin_ = begin_;
  double begin_cpu_ = cpu_seconds(), phase_cpu_ = begin_cpu_;
};

}  // namespace dtm
