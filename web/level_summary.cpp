// The native twin of the WebAssembly decoder's level summaries: the same
// LevelViewer, fed the same chunks, prints one JSON line per level
// (level_summary_json) and a last line with how the stream ended. The
// equivalence test (web/test/wasm_equivalence.mjs) requires the WebAssembly
// decoder to print the very same lines.
//
//   level_summary STREAM.dtm [--chunk BYTES]
//   level_summary STREAM.dtm --time-finest RUNS   best seconds of RUNS decodes
//                                                 to the finest mesh (bench/viewer.sh)
//   level_summary STREAM.dtm --time-levels RUNS   best seconds of RUNS decodes
//                                                 of every level's view, as the page does
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "codec/decode.h"
#include "web/level_view.h"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: level_summary STREAM.dtm [--chunk BYTES | --time-finest RUNS | --time-levels RUNS]\n");
  return 2;
}

// Runs `decode` (which returns the tetrahedra it made, or -1) RUNS times
// and prints the best time and the tetrahedra.
template <class Decode>
int print_best_time(int runs, Decode&& decode) {
  double best = 1e300;
  long long tetrahedra = 0;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    tetrahedra = decode();
    if (tetrahedra < 0) return 1;
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::printf("{\"seconds\": %.6f, \"tetrahedra\": %lld}\n", best, tetrahedra);
  return 0;
}

// To the finest mesh in one batch, as meshdec decodes.
long long decode_finest(const std::vector<uint8_t>& bytes) {
  dtm::ProgressiveDecoder decoder;
  if (!dtm::decode_stream(bytes, decoder).ok()) return -1;
  return static_cast<long long>(decoder.carved_cells().size());
}

// Every level's view, the whole stream fed at once, as the page makes them.
long long decode_levels(const std::vector<uint8_t>& bytes) {
  dtm::LevelViewer viewer;
  if (!viewer.feed(bytes).ok()) return -1;
  long long tetrahedra = 0;
  while (viewer.has_level()) tetrahedra = static_cast<long long>(viewer.take_level().cells.size());
  return tetrahedra;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && argc != 4) return usage();
  size_t chunk = 65536;
  int runs = 0;
  bool levels = false;
  if (argc == 4) {
    const long n = std::atol(argv[3]);
    if (n <= 0) return usage();
    if (std::strcmp(argv[2], "--chunk") == 0)
      chunk = static_cast<size_t>(n);
    else if (std::strcmp(argv[2], "--time-finest") == 0)
      runs = static_cast<int>(n);
    else if (std::strcmp(argv[2], "--time-levels") == 0)
      runs = static_cast<int>(n), levels = true;
    else
      return usage();
  }
  std::ifstream file(argv[1], std::ios::binary);
  if (!file) {
    std::fprintf(stderr, "level_summary: cannot open %s\n", argv[1]);
    return 1;
  }
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (runs > 0)
    return print_best_time(runs, [&] { return levels ? decode_levels(bytes) : decode_finest(bytes); });

  dtm::LevelViewer viewer;
  dtm::Status status;
  for (size_t at = 0; at < bytes.size() && status.ok(); at += chunk) {
    status = viewer.feed(std::span(bytes.data() + at, std::min(chunk, bytes.size() - at)));
    while (viewer.has_level())
      std::printf("%s\n", dtm::level_summary_json(viewer.decoder(), viewer.take_level()).c_str());
  }
  std::printf("%s\n", dtm::end_summary_json(viewer.finish()).c_str());
  return 0;
}
