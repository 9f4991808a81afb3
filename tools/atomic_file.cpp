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
  StagedFiles staged(rename);
  staged.stage(files);
  staged.commit();
}

StagedFiles::~StagedFiles() {
  if (committed_) {
    forget_kept();
    return;
  }
  for (const File& f : files_)
    if (!f.in_place) std::remove(temporary_for(f.path).c_str());
}

void StagedFiles::stage(const std::vector<std::pair<std::string, std::string>>& files) {
  for (const auto& [name, bytes] : files) {
    File f;
    f.name = name;
    const Target t = target_of(name);
    f.path = t.path;
    f.in_place = t.in_place;
    if (f.in_place)
      f.bytes = bytes;
    else
      write_temporary(name, f.path, bytes);  // (throws: the destructor removes the others)
    files_.push_back(std::move(f));
  }
}

void StagedFiles::forget_kept() {
  for (File& f : files_)
    if (f.before == Before::kKept) std::remove(kept_for(f.path).c_str()), f.before = Before::kAbsent;
}

void StagedFiles::commit() {
  const RenameFile rename = rename_ ? rename_ : &std::rename;
  // A rename fails on a directory: found before any file is replaced, so
  // that a failed write of several files (.node and .ele, .gltf and .bin)
  // leaves none of them.
  for (const File& f : files_) {
    std::error_code ec;
    if (!f.in_place && std::filesystem::is_directory(f.path, ec))
      throw std::runtime_error(f.name + ": cannot replace: " + std::strerror(EISDIR));
  }
  // A rename can fail for other reasons too (a file made immutable, one a
  // sticky folder keeps for its owner). Each target that exists is kept
  // under a second name, a hard link, until every file is in place, so that
  // a rename failing partway puts back the files replaced before it. Where
  // no link can be made (a file system without them) that file cannot be
  // put back, and is left as written.
  for (File& f : files_) {
    std::error_code ec;
    f.before = Before::kAbsent;
    if (f.in_place || !std::filesystem::exists(std::filesystem::symlink_status(f.path, ec))) continue;
    const std::string kept = kept_for(f.path);
    std::remove(kept.c_str());  // (one a run of this process number left)
    f.before = ::link(f.path.c_str(), kept.c_str()) == 0 ? Before::kKept : Before::kUnkept;
  }
  for (size_t i = 0; i < files_.size(); ++i) {
    if (files_[i].in_place) continue;
    if (rename(temporary_for(files_[i].path).c_str(), files_[i].path.c_str()) != 0) {
      const int e = errno;
      put_back(i);
      for (size_t k = i; k < files_.size(); ++k) {
        if (files_[k].before == Before::kKept) std::remove(kept_for(files_[k].path).c_str());
        files_[k].before = Before::kAbsent;
      }
      throw std::runtime_error(files_[i].name + ": cannot replace: " + std::strerror(e));
    }
  }
  committed_ = true;
  // Devices and pipes last: written into, not replaced (not atomically).
  for (const File& f : files_)
    if (f.in_place) write_in_place(f.name, f.path, f.bytes);
}

void StagedFiles::undo() {
  if (!committed_) return;
  put_back(files_.size());
  committed_ = false;
}

void StagedFiles::put_back(size_t count) {
  for (size_t i = 0; i < count; ++i) {
    File& f = files_[i];
    if (f.in_place) continue;
    // (A file that cannot be put back keeps its copy beside it.)
    if (f.before == Before::kKept && std::rename(kept_for(f.path).c_str(), f.path.c_str()) != 0)
      f.before = Before::kUnkept;
    else if (f.before == Before::kKept)
      f.before = Before::kAbsent;
    else if (f.before == Before::kAbsent)
      std::remove(f.path.c_str());
  }
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
