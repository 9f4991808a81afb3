#include "tools/phase_display.h"

#include <utility>

#if defined(__unix__) && !defined(__EMSCRIPTEN__)
#include <sys/resource.h>
#endif

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

double PhaseDisplay::cpu_seconds() {
#if defined(__unix__) && !defined(__EMSCRIPTEN__)
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  const auto s = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return s(usage.ru_utime) + s(usage.ru_stime);
#else
  return 0;
#endif
}

double PhaseDisplay::cores_busy(Clock::time_point since, double cpu_since) {
  const double wall = seconds(Clock::now() - since);
  return wall > 0 ? (cpu_seconds() - cpu_since) / wall : 0;
}

void PhaseDisplay::start(std::string_view phase) {
  end_current();
  current_.assign(phase);
  phase_begin_ = Clock::now();
  phase_cpu_ = cpu_seconds();
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
    std::fprintf(stderr, "%s%9.3f s %5.2f cores %8.0f MiB %8.0f MiB peak  %s\n", prefix_.c_str(),
                 seconds(Clock::now() - phase_begin_), cores_busy(phase_begin_, phase_cpu_), now, peak,
                 current_.c_str());
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
    std::fprintf(stderr, "%s%9.3f s %5.2f cores %8.0f MiB %8.0f MiB peak  in all\n", prefix_.c_str(),
                 seconds(Clock::now() - begin_), cores_busy(begin_, begin_cpu_), now, peak);
  }
}

}  // namespace dtm
