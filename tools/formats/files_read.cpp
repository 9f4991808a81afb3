#include "tools/formats/files_read.h"

#include <algorithm>
#include <mutex>

namespace dtm {
namespace {

std::mutex guard;
std::vector<std::string>& read_so_far() {
  static std::vector<std::string> files;
  return files;
}

}  // namespace

void note_file_read(const std::string& path) {
  const std::lock_guard<std::mutex> lock(guard);
  std::vector<std::string>& files = read_so_far();
  if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
}

std::vector<std::string> files_read() {
  const std::lock_guard<std::mutex> lock(guard);
  return read_so_far();
}

}  // namespace dtm
