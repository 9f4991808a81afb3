// Reading a whole input (a file or standard input) in chunks, for the
// decoder tools: the progressive decoder is fed as the bytes arrive.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>

namespace dtm {

// Calls `consume` with each chunk of `path` ("-" = standard input) until the
// input ends or `consume` returns false. Throws std::runtime_error naming the
// path if it cannot be read.
void read_in_chunks(const std::string& path, const std::function<bool(std::span<const uint8_t>)>& consume);

}  // namespace dtm
