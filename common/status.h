// Errors as values, the one error mechanism of every library in this project:
// a function that can fail returns a Status, or a StatusOr<T> holding either
// its result or the reason it has none. The codes are stable (tools map them
// to exit statuses and tests assert them); new codes are only ever appended.
// Exceptions stay outside: where CGAL or the standard library throws, the
// door that calls it converts the exception into a Status.
#pragma once

#include <cstdlib>
#include <optional>
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
  kInvalidInput,   // the caller's data or options cannot make what was asked
                   // (fewer than 4 points, all coplanar, qbits out of range)
  kInternal,       // a library we call failed (a CGAL exception, no memory)
};

class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  static Status Ok() { return {}; }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }

  // The same status with `context` and ": " before its message ("level 3 at
  // byte 120: layer checksum mismatch").
  Status with_context(const std::string& context) const {
    return ok() ? *this : Status(code_, context + ": " + message_);
  }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

const char* to_string(StatusCode code);

// The two failures most code names, made in one place: the caller's data
// or options cannot make what was asked, and bytes that contradict the
// format.
inline Status invalid_input(std::string what) { return {StatusCode::kInvalidInput, std::move(what)}; }
inline Status corrupt(std::string what) { return {StatusCode::kCorrupt, std::move(what)}; }

// A value or the Status that explains why there is none.
template <class T>
class StatusOr {
 public:
  StatusOr(T value) : value_(std::move(value)) {}         // NOLINT: implicit, as absl's
  StatusOr(Status status) : status_(std::move(status)) {  // NOLINT
    if (status_.ok()) status_ = {StatusCode::kInternal, "StatusOr made from an ok Status"};
  }

  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }

  // Only when ok(): reading the value of an error is a bug, and aborts.
  T& value() & { return checked(), *value_; }
  const T& value() const& { return checked(), *value_; }
  T&& value() && { return checked(), std::move(*value_); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  void checked() const {
    if (!value_) std::abort();
  }
  Status status_;
  std::optional<T> value_;
};

#define DTM_STATUS_CONCAT_INNER(a, b) a##b
#define DTM_STATUS_CONCAT(a, b) DTM_STATUS_CONCAT_INNER(a, b)

// Returns the status of `expr` from the calling function if it is an error.
#define DTM_RETURN_IF_ERROR(expr)              \
  do {                                         \
    ::dtm::Status dtm_status_ = (expr);        \
    if (!dtm_status_.ok()) return dtm_status_; \
  } while (0)

// `lhs = value of expr` (a StatusOr), or returns its status from the calling
// function. `lhs` may declare a variable: DTM_ASSIGN_OR_RETURN(auto x, f());
// NOLINTBEGIN(bugprone-macro-parentheses): `lhs` is a declaration, `tmp` a name.
#define DTM_ASSIGN_OR_RETURN(lhs, expr) \
  DTM_ASSIGN_OR_RETURN_IMPL(DTM_STATUS_CONCAT(dtm_status_or_, __LINE__), lhs, expr)
#define DTM_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                              \
  if (!tmp.ok()) return tmp.status();             \
  lhs = std::move(tmp).value()
// NOLINTEND(bugprone-macro-parentheses)

// Internal invariants: a failure is a bug in this project, not bad input, so
// it aborts with the place and the condition (also in release builds).
#define DTM_CHECK(condition)                                               \
  do {                                                                     \
    if (!(condition)) ::dtm::check_failed(__FILE__, __LINE__, #condition); \
  } while (0)
[[noreturn]] void check_failed(const char* file, int line, const char* condition);

}  // namespace dtm
