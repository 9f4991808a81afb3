// Errors as values: every parsing and decoding step returns a Status. The
// codes are stable (tools map them to exit statuses and tests assert them).
#pragma once

#include <string>
#include <utility>

namespace dtm {

enum class StatusCode {
  kOk = 0,
  kNeedMoreInput,  // not an error: a progressive decoder waits for bytes
  kTruncated,      // the input ended inside a layer: the levels before it stand
  kCorrupt,        // the bytes contradict the format (checksum, count, range)
  kUnsupported,    // a future version or an unknown flag
  kNotDtm,         // wrong magic: not one of our streams
  kLimitExceeded,  // a claim beyond the caller's resource limits
};

class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  static Status Ok() { return {}; }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

const char* to_string(StatusCode code);

#define DTM_RETURN_IF_ERROR(expr)        \
  do {                                   \
    ::dtm::Status dtm_status_ = (expr);  \
    if (!dtm_status_.ok()) return dtm_status_; \
  } while (0)

}  // namespace dtm
