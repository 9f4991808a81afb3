// The TetGen reader on arbitrary bytes: a FormatError or a valid point set,
// never a crash. The first byte picks .node or .ele.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fuzz_check.h"
#include "tools/formats/tetgen.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const std::string path = "/tmp/dtm_fuzz_tetgen_" + std::to_string(getpid());
  const bool ele = data[0] & 1;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data + 1, 1, size - 1, f);
  std::fclose(f);
  try {
    if (ele) {
      for (const auto& t : dtm::read_tetgen_ele(path, 64, data[0] >> 7))
        for (uint32_t v : t) FUZZ_CHECK(v < 64);
    } else {
      const auto node = dtm::read_tetgen_node(path);
      for (const auto& p : node.points)
        FUZZ_CHECK(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z));
    }
  } catch (const dtm::FormatError&) {
  }
  std::remove(path.c_str());
  return 0;
}
