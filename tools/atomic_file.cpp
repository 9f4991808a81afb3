#include "atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace dtm {

namespace {

std::string temporary_for(const std::string& path) { return path + ".tmp." + std::to_string(::getpid()); }
// Where a file about to be replaced is kept until its fellows are in place.
std::string kept_for(const std::string& path) { return path + ".old." + std::to_string(::getpid()); }

// `name`: the path as the caller gave it, for the message.
void write_temporary(const std::string& name, const std::string& path, std::string_view bytes) {
  const std::string tmp = temporary_for(path);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw std::runtime_error(name + ": cannot write: " + std::strerror(errno));
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
  const int saved = errno;
  if (std::fclose(f) != 0 || !ok) {
    std::remove(tmp.c_str());
    throw std::runtime_error(name + ": cannot write: " + std::strerror(saved));
  }
}

// Where a path's bytes go: a symbolic link's target (the link stays), and
// whether that is a file to replace or one to write into as it is (a
// device such as /dev/null, a FIFO, a socket: replacing it with a plain
// file would break the system, or leave the reader at the other end
// nothing).
struct Target {
  std::string path;
  bool in_place = false;
};
Target target_of(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // What the path is, the kernel following every link (/dev/stdout to a
  // pipe too, whose /proc link names no path): a device, FIFO or socket is
  // written into through the path as given.
  const fs::file_status st = fs::status(path, ec);
  if (!ec && fs::exists(st) && !fs::is_regular_file(st) && !fs::is_directory(st)) return {path, true};
  // A file to replace: found link by link (a link whose target does not
  // exist yet names the file to make).
  fs::path p = path;
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) break;
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  return {p.string(), false};
}

void write_in_place(const std::string& name, const std::string& path, std::string_view bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error(name + ": cannot write: " + std::strerror(errno));
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size() && std::fflush(f) == 0;
  const int saved = errno;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error(name + ": cannot write: " + std::strerror(saved));
}

}  // namespace

void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files) {
  write_files_atomically(files, &std::rename);
}

void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files,
                            RenameFile rename) {
  std::vector<Target> targets;
  targets.reserve(files.size());
  for (const auto& [path, bytes] : files) targets.push_back(target_of(path));
  size_t written = 0;
  const auto remove_temporaries = [&](size_t from, size_t to) {
    for (size_t i = from; i < to; ++i)
      if (!targets[i].in_place) std::remove(temporary_for(targets[i].path).c_str());
  };
  try {
    for (; written < files.size(); ++written)
      if (!targets[written].in_place)
        write_temporary(files[written].first, targets[written].path, files[written].second);
  } catch (...) {
    remove_temporaries(0, written);
    throw;
  }
  // A rename fails on a directory: found before any file is replaced, so
  // that a failed write of several files (.node and .ele, .gltf and .bin)
  // leaves none of them.
  for (size_t i = 0; i < files.size(); ++i) {
    std::error_code ec;
    if (!targets[i].in_place && std::filesystem::is_directory(targets[i].path, ec)) {
      remove_temporaries(0, files.size());
      throw std::runtime_error(files[i].first + ": cannot replace: " + std::strerror(EISDIR));
    }
  }
  // A rename can fail for other reasons too (a file made immutable, one a
  // sticky folder keeps for its owner). Each target that exists is kept
  // under a second name, a hard link, until every file is in place, so that
  // a rename failing partway puts back the files replaced before it. Where
  // no link can be made (a file system without them) that file cannot be
  // put back, and is left as written.
  enum class Before : uint8_t { kAbsent, kKept, kUnkept };
  std::vector<Before> before(files.size(), Before::kAbsent);
  for (size_t i = 0; i < files.size(); ++i) {
    std::error_code ec;
    if (targets[i].in_place || !std::filesystem::exists(std::filesystem::symlink_status(targets[i].path, ec)))
      continue;
    const std::string kept = kept_for(targets[i].path);
    std::remove(kept.c_str());  // (one a run of this process number left)
    before[i] = ::link(targets[i].path.c_str(), kept.c_str()) == 0 ? Before::kKept : Before::kUnkept;
  }
  const auto forget_kept = [&] {
    for (size_t i = 0; i < files.size(); ++i)
      if (before[i] == Before::kKept) std::remove(kept_for(targets[i].path).c_str());
  };
  for (size_t i = 0; i < files.size(); ++i) {
    if (targets[i].in_place) continue;
    const std::string& path = targets[i].path;
    if (rename(temporary_for(path).c_str(), path.c_str()) != 0) {
      const int e = errno;
      for (size_t j = 0; j < i; ++j) {
        if (targets[j].in_place) continue;
        // (A file that cannot be put back keeps its copy beside it.)
        if (before[j] == Before::kKept &&
            std::rename(kept_for(targets[j].path).c_str(), targets[j].path.c_str()) != 0)
          before[j] = Before::kUnkept;
        else if (before[j] == Before::kAbsent)
          std::remove(targets[j].path.c_str());
      }
      remove_temporaries(i, files.size());
      forget_kept();
      throw std::runtime_error(files[i].first + ": cannot replace: " + std::strerror(e));
    }
  }
  forget_kept();
  // Devices and pipes last: written into, not replaced (not atomically).
  for (size_t i = 0; i < files.size(); ++i)
    if (targets[i].in_place) write_in_place(files[i].first, targets[i].path, files[i].second);
}

void check_writable(const std::string& path, const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (const std::string& input : inputs)
    if (input != "-" && fs::exists(input, ec) && fs::exists(path, ec) && fs::equivalent(input, path, ec))
      throw std::invalid_argument(path + ": is the input: write the output elsewhere");
  if (fs::is_directory(path, ec)) throw std::invalid_argument(path + ": is a directory");
  const Target t = target_of(path);
  if (t.in_place) {
    if (::access(t.path.c_str(), W_OK) != 0)
      throw std::invalid_argument(path + ": cannot write: " + std::strerror(errno));
    return;
  }
  // The temporary file goes beside the target.
  const fs::path folder =
      fs::path(t.path).parent_path().empty() ? fs::path(".") : fs::path(t.path).parent_path();
  if (!fs::is_directory(folder, ec))
    throw std::invalid_argument(path + ": cannot write: no folder " + folder.string());
  if (::access(folder.c_str(), W_OK) != 0)
    throw std::invalid_argument(path + ": cannot write in " + folder.string() + ": " + std::strerror(errno));
  // access() answers by the permission bits (and a read-only mount): a
  // folder whose files cannot be made whatever the bits say (/sys and
  // /proc to root) is found by making the temporary file there, now,
  // rather than after the work.
  const std::string probe = temporary_for(t.path);
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f)
    throw std::invalid_argument(path + ": cannot write in " + folder.string() + ": " + std::strerror(errno));
  std::fclose(f);
  std::remove(probe.c_str());
}

}  // namespace dtm
