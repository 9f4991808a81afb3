#include "stream_input.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace dtm {

void read_in_chunks(const std::string& path, const std::function<bool(std::span<const uint8_t>)>& consume) {
  std::FILE* f = path == "-" ? stdin : std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error(path + ": cannot open: " + std::strerror(errno));
  std::vector<uint8_t> chunk(1 << 16);
  bool more = true;
  while (more) {
    const size_t n = std::fread(chunk.data(), 1, chunk.size(), f);
    if (n > 0) more = consume({chunk.data(), n});
    if (n < chunk.size()) {
      if (std::ferror(f)) {
        const int e = errno;  // (a directory: "Is a directory")
        if (f != stdin) std::fclose(f);
        throw std::runtime_error(path + ": cannot read: " + std::strerror(e));
      }
      break;
    }
  }
  if (f != stdin) std::fclose(f);
}

}  // namespace dtm
