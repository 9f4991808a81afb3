// Writes a whole file or nothing: the bytes go to a temporary file beside the
// target, which is renamed over it only once complete. A symbolic link's
// target is written (the link stays); a device, FIFO or socket (/dev/null,
// a named pipe) is written into as it is, after the files.
#pragma once

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

// Said before the work rather than after it: throws std::invalid_argument
// naming `path` if write_files_atomically() could not write it (its folder
// missing or not writable, a directory in its place) or if it is one of
// `inputs` (which the work reads: replacing it would lose it).
void check_writable(const std::string& path, const std::vector<std::string>& inputs = {});

}  // namespace dtm
