#include "status.h"

namespace dtm {

const char* to_string(StatusCode code) {
  switch (code) {
    case StatusCode::kOk: return "ok";
    case StatusCode::kNeedMoreInput: return "need more input";
    case StatusCode::kTruncated: return "truncated";
    case StatusCode::kCorrupt: return "corrupt";
    case StatusCode::kUnsupported: return "unsupported";
    case StatusCode::kNotDtm: return "not a dtm stream";
    case StatusCode::kLimitExceeded: return "limit exceeded";
  }
  return "?";
}

}  // namespace dtm
