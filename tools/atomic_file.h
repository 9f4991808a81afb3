// Writes a whole file or nothing: the bytes go to a temporary file beside the
// target, which is renamed over it only once complete. A symbolic link's
// target is written (the link stays); a device, FIFO or socket (/dev/null,
// a named pipe) is written into as it is, after the files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace dtm {

// Several files that belong together (a TetGen .node and its .ele, a stream
// and its report): every one is written to its temporary file first, and
// only when all are complete are they renamed into place. Throws
// std::runtime_error naming the path if anything fails; the targets are then
// left as they were (but a file no hard link could keep: see the .cpp).
void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files);
// The same, each temporary file put in place by `rename` (std::rename's
// contract): what the tests use to make a rename fail partway.
using RenameFile = int (*)(const char* from, const char* to);
void write_files_atomically(const std::vector<std::pair<std::string, std::string>>& files, RenameFile rename);

// The same in two steps, for files written by several processes that stand
// or fall together (meshdec's pieces on MPI ranks): stage() writes each
// file to its temporary beside its target, commit() renames them all into
// place (a rename failing partway puts back those before it, and throws),
// and undo() puts back what commit() replaced, where another process's
// commit failed. Destroyed, it removes what was staged and not committed,
// and forgets the files a commit replaced.
class StagedFiles {
 public:
  StagedFiles() = default;
  explicit StagedFiles(RenameFile rename) : rename_(rename) {}
  ~StagedFiles();
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;

  void stage(const std::vector<std::pair<std::string, std::string>>& files);
  void commit();
  void undo();

 private:
  enum class Before : uint8_t { kAbsent, kKept, kUnkept };
  struct File {
    std::string name;  // as the caller gave it, for messages
    std::string path;  // where the bytes go (a link followed)
    bool in_place = false;
    std::string bytes;  // an in-place file's, written at commit()
    Before before = Before::kAbsent;
  };
  void forget_kept();
  void put_back(size_t count);  // the first `count` files as they were before commit()

  RenameFile rename_ = nullptr;
  std::vector<File> files_;
  bool committed_ = false;
};

// Said before the work rather than after it: throws std::invalid_argument
// naming `path` if write_files_atomically() could not write it (its folder
// missing or not writable, a directory in its place) or if it is one of
// `inputs` (which the work reads: replacing it would lose it).
void check_writable(const std::string& path, const std::vector<std::string>& inputs = {});

}  // namespace dtm
