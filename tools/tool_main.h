// What every tool shares around its own work: --help with its examples,
// --version, and one answer to any error (a message naming the tool, exit 1;
// 2 for a command line it cannot take).
#pragma once

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#ifdef __GLIBC__  // (the standard headers above say)
#include <malloc.h>
#endif

#include "codec/stream/format.h"

namespace dtm {

// The project's version (CMake's project(VERSION)) and the stream versions
// it reads; meshenc also says which it writes (the oldest that holds what a
// stream carries, codec/stream/format.h).
inline std::string version_text(const char* tool) {
  const auto v = [](int major) { return std::to_string(major) + "." + std::to_string(kVersionMinor); };
  std::string text = std::string(tool) + " (dtmesh " DTM_VERSION "): reads .dtm " +
                     std::to_string(kOldestVersionMajor) + ".x to " + std::to_string(kVersionMajor) + ".x";
  if (std::string_view(tool) == "meshenc")
    text += "; writes .dtm " + v(kVersionMajorUnbricked) + ", " + v(kVersionMajorBricked) +
            " with --bricks, " + v(kVersionMajorRegions) + " with regions or tagged faces, " +
            v(kVersionMajorCellData) + " with cell data or --keep-order, " + v(kVersionMajorNodeLabels) +
            " with --keep-order of a file with its own node ids, " + v(kVersionMajorExactClosing) +
            " with --exact, " + v(kVersionMajorBrickedRegions) + " with --bricks and regions, " +
            v(kVersionMajorBrickedCellData) + " with --bricks and cell data, " +
            v(kVersionMajorBrickedFaces) + " with --bricks and tagged faces; --preset paper " +
            v(kVersionMajorWithoutValues) + ", or " + v(kVersionMajorWithValues) + " with values";
  return text;
}

// Parses the command line into a Command (filled by add_options(app, command))
// and runs run(command). Everything is inside the try: CLI11 and the readers
// may throw, and so may an allocation.
// glibc's malloc, told to give memory back: by default it serves blocks
// below a threshold that grows to 32 MB from its arenas, which keep what
// is freed, so that a bunny_1m encoding held 170 MB more than it used
// (blocks' tetrahedralizations, freed one after another). Blocks of 1 MiB
// and more are mapped and unmapped on their own, and a free arena's top
// is trimmed beyond 1 MiB: its peak fell by 11% (533 -> 464 MB), its time
// within the noise.
inline void return_freed_memory() {
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 20);
#endif
}

// The other side of that trade, for work that runs as one piece of a few
// large phases (meshenc's whole levels): every block of 1 MiB and more
// mapped on its own makes each phase's arrays fresh pages, every page a
// fault on the thread that touches it first, and on bunny_1m those faults
// were a seventh of meshenc's time (8 s of system time in 60 s of CPU),
// most of it on the main thread between the parallel parts. Here no block
// is mapped on its own: all come from malloc's arenas, whose free tops are
// trimmed beyond 32 MiB, and the encoder hands the free pages back where
// each level ends (give_back_free_heap(), common/release.h). bunny_1m
// whole-level on 2 cores in 30.3-30.7 s against 37.7-39.5 s, on one in
// 46.0 s against 55.5 s, its peak 1.15-1.24 GB against 1.13-1.14 GB
// (docs/SPEED_AND_MEMORY.md). The bricked encoder keeps the lean setting,
// its point being memory: its blocks' tetrahedralizations, freed one after
// another, held 10% more with this setting (755 MB against 683 MB, 50.9 s
// against 57.5 s), 27% more with arenas keeping blocks up to 32 MiB, and
// handing the free pages back after each block made it slower (61.4 s).
inline void keep_freed_memory_between_phases() {
#ifdef __GLIBC__
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 32 << 20);
#endif
}

// The whole of `text` as a finite decimal number (an optional '+'; no
// spaces, no hexadecimal, no inf or nan), or nothing: every number option
// reads its value so.
inline std::optional<double> finite_decimal(std::string_view text) {
  double v = 0;
  const char* end = text.data() + text.size();
  const char* first = text.data() + (!text.empty() && text[0] == '+');  // (from_chars takes no '+')
  const auto [at, ec] = std::from_chars(first, end, v);
  if (text.empty() || ec != std::errc() || at != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

// A number option's check: finite and above 0 (or, `zero`, at least 0),
// said in words (CLI11's own checks print the double range's 309 digits).
inline CLI::Validator finite_number(bool zero) {
  return CLI::Validator(
      [zero](std::string& text) {
        const std::optional<double> number = finite_decimal(text);
        const double v = number.value_or(0);
        if (!number || v < 0 || (v == 0 && !zero))
          return std::string(zero ? "must be a finite number of 0 or more"
                                  : "must be a finite number above 0") +
                 ", got '" + text + "'";
        return std::string();
      },
      zero ? "NUMBER>=0" : "NUMBER>0");
}

// A command line the tool cannot take, found after parsing (options that
// contradict each other, a value of the wrong form): exit 2, as CLI11's own.
// Under mpirun every rank throws it; `print`: this one says it (rank 0).
class UsageError : public std::invalid_argument {
 public:
  explicit UsageError(const std::string& what, bool print = true)
      : std::invalid_argument(what), print_(print) {}
  bool print() const { return print_; }

 private:
  bool print_;
};

// An error every rank of an MPI job throws alike, having agreed on it: only
// the rank told to prints it (rank 0), so that the user reads it once.
class AgreedError : public std::runtime_error {
 public:
  AgreedError(const std::string& what, bool print) : std::runtime_error(what), print_(print) {}
  bool print() const { return print_; }

 private:
  bool print_;
};

// An error as printed: a message may quote a file's bytes (a binary file
// taken for text), which must not reach a terminal as they are.
inline std::string printable(std::string_view message) {
  std::string out;
  for (const char ch : message) {
    const auto c = static_cast<unsigned char>(ch);
    if ((c >= 0x20 && c != 0x7f) || c == '\n' || c == '\t') {
      out += ch;  // (UTF-8's bytes above 0x7f pass: names may be in any script)
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

// This process's rank of an MPI job (0 alone): main() sets it from its
// MpiSession. The ranks run the same command (tools/same_command.h), so an
// error in it is every rank's alike: the first says it.
inline int& tool_rank() {
  static int rank = 0;
  return rank;
}
inline bool another_rank() { return tool_rank() != 0; }

template <class Command, class AddOptions, class Run>
int tool_main(const char* tool, const char* description, const char* examples, int argc, char** argv,
              AddOptions add_options, Run run) {
  return_freed_memory();
  try {
    CLI::App app{std::string(tool) + ": " + description};
    app.footer(examples);
    app.set_version_flag("--version", version_text(tool));
    Command command;
    add_options(app, command);
    // A command line the tool cannot take exits with 2 (as GNU tools and
    // argparse do), after CLI11's message; --help and --version with 0.
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      if (another_rank()) return e.get_exit_code() == 0 ? 0 : 2;  // (rank 0 says it)
      return app.exit(e) == 0 ? 0 : 2;
    }
    return run(command);
  } catch (const UsageError& e) {
    if (e.print() && !another_rank())
      std::fprintf(stderr, "%s: error: %s\n", tool, printable(e.what()).c_str());
    return 2;
  } catch (const AgreedError& e) {
    if (e.print()) std::fprintf(stderr, "%s: error: %s\n", tool, printable(e.what()).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", tool, printable(e.what()).c_str());
    return 1;
  }
}

}  // namespace dtm
