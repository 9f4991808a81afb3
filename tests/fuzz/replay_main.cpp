// Runs a fuzz target on the files of a corpus, without libFuzzer: the seed
// corpus and every past finding then run under ctest with any compiler.
// Usage: replay_fuzz TARGET FILE_OR_DIR... (every target is linked in; the
// build renames each one's LLVMFuzzerTestOneInput, tests/fuzz/CMakeLists.txt).
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>
#include <vector>

#include "replay_targets.h"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  const ReplayTarget* target = nullptr;
  for (const ReplayTarget& t : kReplayTargets)
    if (argc > 1 && std::string_view(argv[1]) == t.name) target = &t;
  if (!target) {
    std::fprintf(stderr, "usage: replay_fuzz TARGET FILE_OR_DIR...; the targets:");
    for (const ReplayTarget& t : kReplayTargets) std::fprintf(stderr, " %s", t.name);
    std::fprintf(stderr, "\n");
    return 2;
  }
  size_t runs = 0;
  for (int i = 2; i < argc; ++i) {
    std::vector<fs::path> files;
    if (fs::is_directory(argv[i])) {
      for (const auto& e : fs::recursive_directory_iterator(argv[i]))
        if (e.is_regular_file()) files.push_back(e.path());
    } else {
      files.push_back(argv[i]);
    }
    for (const auto& f : files) {
      std::ifstream in(f, std::ios::binary);
      if (!in) {
        std::fprintf(stderr, "replay: cannot read %s\n", f.c_str());
        return 2;
      }
      const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
      target->run(bytes.data(), bytes.size());
      ++runs;
    }
  }
  if (runs == 0) {
    std::fprintf(stderr, "replay: no input files\n");
    return 2;
  }
  std::printf("replay: %s: %zu inputs, no finding\n", target->name, runs);
  return 0;
}
