#include "atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace dtm {

namespace {

std::string temporary_for(const std::string& path) { return path + ".tmp." + std::to_string(::getpid()); }

void write_temporary(const std::string& path, std::string_view bytes) {
  const std::string tmp = temporary_for(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw std::runtime_error(path + ": cannot write: " + std::strerror(errno));
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
  const int saved = errno;
  if (std::fclose(f) != 0 || !ok) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot write: " + std::strerror(saved));
  }
}

}  // namespace

void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files) {
  size_t written = 0;
  try {
    for (; written < files.size(); ++written) write_temporary(files[written].first, files[written].second);
  } catch (...) {
    for (size_t i = 0; i < written; ++i) std::remove(temporary_for(files[i].first).c_str());
    throw;
  }
  for (size_t i = 0; i < files.size(); ++i) {
    const std::string& path = files[i].first;
    if (std::rename(temporary_for(path).c_str(), path.c_str()) != 0) {
      const int e = errno;
      for (size_t j = i; j < files.size(); ++j) std::remove(temporary_for(files[j].first).c_str());
      throw std::runtime_error(path + ": cannot replace: " + std::strerror(e));
    }
  }
}

}  // namespace dtm
