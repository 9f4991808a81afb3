// The one error every input reader throws.
#pragma once

#include <stdexcept>

namespace dtm {

// A bad input file: the message names the file, where (line, or byte offset
// in binary data) and the problem: "path:12: expected 4 fields, found 3".
struct FormatError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace dtm
