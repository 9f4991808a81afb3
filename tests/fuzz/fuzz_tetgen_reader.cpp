// The TetGen reader on arbitrary bytes: a FormatError or a valid point set,
// never a crash. The first byte picks .node, .ele or .face (and, for an
// .ele, the index base and whether a second-order one may be read).
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

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
      // (Bit 1: with room for a second-order .ele's edge nodes.)
      std::vector<std::array<uint32_t, 6>> edge_nodes;
      const auto tets =
          dtm::read_tetgen_ele(path, 64, data[0] >> 7, {}, nullptr, (data[0] & 2) ? &edge_nodes : nullptr);
      for (const auto& t : tets)
        for (uint32_t v : t) FUZZ_CHECK(v < 64);
      FUZZ_CHECK(edge_nodes.empty() || edge_nodes.size() == tets.size());
      for (const auto& e : edge_nodes)
        for (uint32_t v : e) FUZZ_CHECK(v < 64);
    } else if ((data[0] & 0x0c) == 0x0c) {
      // (Bits 2 and 3 of a byte with bit 0 clear: a .face.)
      const dtm::FaceFile faces = dtm::read_tetgen_face(path, 64, data[0] >> 7);
      for (const auto& t : faces.faces)
        for (uint32_t v : t) FUZZ_CHECK(v < 64);
      FUZZ_CHECK(faces.markers.empty() || faces.markers.size() == faces.faces.size());
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
