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

// Decodes to the finest mesh RUNS times, as meshdec does (one batch), and
// prints the best time and the tetrahedra.
int time_finest(const std::vector<uint8_t>& bytes, int runs) {
  double best = 1e300;
  size_t tetrahedra = 0;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    dtm::ProgressiveDecoder decoder;
    if (!dtm::decode_stream(bytes, decoder).ok()) return 1;
    tetrahedra = decoder.carved_cells().size();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::printf("{\"seconds\": %.6f, \"tetrahedra\": %zu}\n", best, tetrahedra);
  return 0;
}

// Makes every level's view RUNS times, the whole stream fed at once, and
// prints the best time and the finest level's tetrahedra.
int time_levels(const std::vector<uint8_t>& bytes, int runs) {
  double best = 1e300;
  size_t tetrahedra = 0;
  for (int r = 0; r < runs; ++r) {
    const auto start = std::chrono::steady_clock::now();
    dtm::LevelViewer viewer;
    if (!viewer.feed(bytes).ok()) return 1;
    while (viewer.has_level()) tetrahedra = viewer.take_level().cells.size();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::printf("{\"seconds\": %.6f, \"tetrahedra\": %zu}\n", best, tetrahedra);
  return 0;
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
  if (runs > 0) return levels ? time_levels(bytes, runs) : time_finest(bytes, runs);

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
