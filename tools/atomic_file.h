// Writes a whole file or nothing: the bytes go to a temporary file beside the
// target, which is renamed over it only once complete.
#pragma once

#include <string>
#include <string_view>

namespace dtm {

// Throws std::runtime_error naming the path if anything fails; the target is
// then left as it was.
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace dtm
