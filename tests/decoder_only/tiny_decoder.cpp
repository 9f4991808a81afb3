// A decoder-only program: links dtm_decoder alone (no hierarchy builder, no
// encoder), as the WebAssembly viewer will. It feeds a stream in small
// chunks, as a network would deliver it, and prints each level as it
// completes, checking its cells against the stream's cell hashes when the
// stream has them.
//
//   tiny_decoder STREAM.dtm
#include <cstdio>
#include <fstream>
#include <iterator>
#include <vector>

#include "codec/decode.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: tiny_decoder STREAM.dtm\n");
    return 2;
  }
  std::ifstream file(argv[1], std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (!file.eof() && !file) {
    std::fprintf(stderr, "tiny_decoder: cannot read %s\n", argv[1]);
    return 1;
  }
  dtm::ProgressiveDecoder decoder;
  bool hashes_match = true;
  const auto on_level = [&](const dtm::ProgressiveDecoder& d, const dtm::DecodedLevel& level) {
    const auto cells = d.carved_cells();
    const bool hash_ok =
        !level.cell_hash || dtm::level_cell_hash(d.header().flags, d.points(), cells) == *level.cell_hash;
    hashes_match = hashes_match && hash_ok;
    std::printf("level %d: %u vertices, %zu tetrahedra%s\n", level.level, level.vertices, cells.size(),
                level.cell_hash ? (hash_ok ? ", cell hash verified" : ", CELL HASH DIFFERS") : "");
  };
  for (size_t at = 0; at < bytes.size(); at += 1000) {
    const size_t n = std::min<size_t>(1000, bytes.size() - at);
    const dtm::Status s = decoder.feed(std::span(bytes.data() + at, n), on_level);
    if (!s.ok()) {
      std::fprintf(stderr, "tiny_decoder: %s: %s\n", argv[1], s.message().c_str());
      return 1;
    }
  }
  const dtm::Status end = decoder.finish();
  if (!end.ok()) std::fprintf(stderr, "tiny_decoder: %s: %s\n", argv[1], end.message().c_str());
  return end.ok() && hashes_match ? 0 : 1;
}
