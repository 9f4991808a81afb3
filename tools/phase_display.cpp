#include "tools/phase_display.h"

#include <utility>

namespace dtm {
namespace {
double seconds(std::chrono::steady_clock::duration d) { return std::chrono::duration<double>(d).count(); }

// The process's resident memory now and at its peak so far, MiB (Linux:
// /proc/self/status); 0 where unknown.
std::pair<double, double> resident_mib() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return {0, 0};
  char line[256];
  double now = 0, peak = 0;
  while (std::fgets(line, sizeof line, f)) {
    unsigned long kib = 0;
    if (std::sscanf(line, "VmRSS: %lu kB", &kib) == 1) now = kib / 1024.0;
    if (std::sscanf(line, "VmHWM: %lu kB", &kib) == 1) peak = kib / 1024.0;
  }
  std::fclose(f);
  return {now, peak};
}
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
    const auto [now, peak] = resident_mib();
    std::fprintf(stderr, "%s%9.3f s %8.0f MiB %8.0f MiB peak  %s\n", prefix_.c_str(),
                 seconds(Clock::now() - phase_begin_), now, peak, current_.c_str());
  }
  current_.clear();
}

void PhaseDisplay::finish() {
  if (finished_) return;
  finished_ = true;
  end_current();
  clear();
  if (timings_) {
    const auto [now, peak] = resident_mib();
    std::fprintf(stderr, "%s%9.3f s %8.0f MiB %8.0f MiB peak  in all\n", prefix_.c_str(),
                 seconds(Clock::now() - begin_), now, peak);
  }
}

}  // namespace dtm
