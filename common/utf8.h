// UTF-8 text cut to a number of bytes without cutting a character in two
// (names a stream or a file format holds in a fixed number of bytes).
#pragma once

#include <cstddef>
#include <string>

namespace dtm {

// `text`'s first `bytes` bytes, less the start of a character they would
// cut (a continuation byte follows the cut).
inline std::string utf8_prefix(std::string text, size_t bytes) {
  if (text.size() <= bytes) return text;
  size_t end = bytes;
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;  // a continuation byte
  text.resize(end);
  return text;
}

}  // namespace dtm
