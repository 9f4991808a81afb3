#include "common/status.h"

#include <cstdio>
#include <cstdlib>

namespace dtm {

const char* to_string(StatusCode code) {
  switch (code) {
    case StatusCode::kOk:
      return "ok";
    case StatusCode::kNeedMoreInput:
      return "need more input";
    case StatusCode::kTruncated:
      return "truncated";
    case StatusCode::kCorrupt:
      return "corrupt";
    case StatusCode::kUnsupported:
      return "unsupported";
    case StatusCode::kNotDtm:
      return "not a dtm stream";
    case StatusCode::kLimitExceeded:
      return "limit exceeded";
    case StatusCode::kInvalidInput:
      return "invalid input";
    case StatusCode::kInternal:
      return "internal error";
  }
  return "?";
}

void check_failed(const char* file, int line, const char* condition) {
  std::fprintf(stderr, "dtmesh: internal error at %s:%d: %s does not hold\n", file, line, condition);
  std::abort();
}

}  // namespace dtm
