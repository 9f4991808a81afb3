#include "tools/phase_display.h"

namespace dtm {
namespace {
double seconds(std::chrono::steady_clock::duration d) { return std::chrono::duration<double>(d).count(); }
}  // namespace

void PhaseDisplay::start(std::string_view phase) {
  end_current();
  current_.assign(phase);
  phase_begin_ = Clock::now();
  if (live_) {
    std::fprintf(stderr, "\r[%6.1f s] %s\033[K", seconds(phase_begin_ - begin_), current_.c_str());
    std::fflush(stderr);
    drawn_ = true;
  }
}

void PhaseDisplay::clear() {
  if (!drawn_) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  drawn_ = false;
}

void PhaseDisplay::end_current() {
  if (current_.empty()) return;
  if (timings_) {
    clear();
    std::fprintf(stderr, "%9.3f s  %s\n", seconds(Clock::now() - phase_begin_), current_.c_str());
  }
  current_.clear();
}

void PhaseDisplay::finish() {
  if (finished_) return;
  finished_ = true;
  end_current();
  clear();
  if (timings_) std::fprintf(stderr, "%9.3f s  in all\n", seconds(Clock::now() - begin_));
}

}  // namespace dtm
