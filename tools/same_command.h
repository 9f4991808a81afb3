// Under mpirun every rank must run the same command: ranks given other
// options or other inputs build other blocks, so that the stream they write
// together is neither's, or they wait on each other at different points
// forever (a rank with --no-fields kept the two others waiting; one with
// --qbits 12 wrote a stream the decoder refuses; meshdec's ranks at other
// levels wrote pieces of two levels). Checked first, before any work: the
// command lines, but for what each rank may set for itself (--threads,
// -v, -q), and the size of every file they name.
#pragma once

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "tools/mpi_session.h"
#include "tools/thread_budget.h"

namespace dtm {

// What must be alike on every rank: the arguments, each input file's
// followed by its size, but for --threads (with its value), -v and -q.
// (An output may stand on one node's disk and not another's: its size is
// not compared.)
inline std::string command_for_agreement(int argc, char** argv) {
  // (A --threads a rank cannot take, outside add_threads_option()'s range,
  // is not its own choice: it would leave the others waiting while it stops
  // at its command line. Kept, as given.)
  const auto threads_taken = [](std::string_view v) {
    int n = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
    return ec == std::errc() && end == v.data() + v.size() && n >= 1 && n <= kMostThreadsAsked;
  };
  const auto own_flags = [](std::string_view a) {  // -v, -q, -qv, --verbose[=...], --quiet[=...]
    if (a.starts_with("--verbose") || a.starts_with("--quiet"))
      return a == "--verbose" || a == "--quiet" || a.starts_with("--verbose=") || a.starts_with("--quiet=");
    return a.size() >= 2 && a[0] == '-' && a.find_first_not_of("qv", 1) == std::string_view::npos;
  };
  std::string out;
  bool output = false;  // the argument is an output's path
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    if (a == "--threads" && i + 1 < argc && threads_taken(argv[i + 1])) {
      ++i;
      continue;
    }
    if ((a.starts_with("--threads=") && threads_taken(a.substr(10))) || own_flags(a)) continue;
    out.append(a);
    std::error_code ec;
    if (!output && !a.starts_with("-") && std::filesystem::is_regular_file(std::string(a), ec))
      out += " (" + std::to_string(std::filesystem::file_size(std::string(a), ec)) + " bytes)";
    out += '\n';
    output = a == "-o" || a == "--output" || a == "--report";
  }
  return out;
}

// On every rank: false (and rank 0 has said which ranks differ) where the
// ranks' commands are not alike. A single process agrees with itself.
inline bool ranks_run_the_same_command(MpiSession& mpi, const char* tool, int argc, char** argv) noexcept {
  if (mpi.size() <= 1) return true;
  try {
    const std::string mine = command_for_agreement(argc, argv);
    const auto all = mpi.all_gather({reinterpret_cast<const uint8_t*>(mine.data()), mine.size()});
    std::vector<int> other;
    for (size_t r = 1; r < all.size(); ++r)
      if (all[r] != all[0]) other.push_back(static_cast<int>(r));
    if (other.empty()) return true;
    if (mpi.rank() == 0) {
      // The first line that differs, rank 0's and the first other rank's.
      const auto lines = [](const std::vector<uint8_t>& bytes) {
        std::vector<std::string> out(1);
        for (uint8_t b : bytes) {
          if (b == '\n')
            out.emplace_back();
          else
            out.back().push_back(static_cast<char>(b));
        }
        return out;
      };
      const std::vector<std::string> a = lines(all[0]), b = lines(all[static_cast<size_t>(other[0])]);
      size_t k = 0;
      while (k < a.size() && k < b.size() && a[k] == b[k]) ++k;
      const auto shown = [](const std::vector<std::string>& l, size_t k) {
        return k < l.size() && !l[k].empty() ? "'" + l[k] + "'" : std::string("nothing more");
      };
      std::string ranks;
      for (int r : other) ranks += (ranks.empty() ? "" : ", ") + std::to_string(r);
      // The same argument, a file one rank sees and another does not (a
      // node's own disk, another working folder), or sees at another size.
      const auto bare = [](const std::vector<std::string>& l, size_t k) {
        if (k >= l.size()) return std::string();
        const size_t at = l[k].rfind(" (");
        return at != std::string::npos && l[k].ends_with(" bytes)") ? l[k].substr(0, at) : l[k];
      };
      const auto seen = [&](const std::vector<std::string>& l, size_t k) {
        return l[k] == bare(l, k)
                   ? std::string("cannot read it")
                   : "sees " + l[k].substr(bare(l, k).size() + 2, l[k].size() - bare(l, k).size() - 3);
      };
      if (k < a.size() && k < b.size() && bare(a, k) == bare(b, k)) {
        std::fprintf(stderr,
                     "%s: error: the ranks do not see the same file '%s': rank 0 %s, rank %d %s (every rank "
                     "must read the same input)\n",
                     tool, bare(a, k).c_str(), seen(a, k).c_str(), other[0], seen(b, k).c_str());
        return false;
      }
      std::fprintf(stderr,
                   "%s: error: the ranks were not given the same command (every rank must run the same "
                   "options on the same files; only --threads, -v and -q may differ): rank%s %s differ%s "
                   "from rank 0, rank %d with %s where rank 0 has %s\n",
                   tool, other.size() > 1 ? "s" : "", ranks.c_str(), other.size() > 1 ? "" : "s", other[0],
                   shown(b, k).c_str(), shown(a, k).c_str());
    }
    return false;
  } catch (const std::exception& e) {  // (called from main, outside tool_main's answer to errors)
    std::fprintf(stderr, "%s: error: %s\n", tool, e.what());
    return false;
  }
}

}  // namespace dtm
