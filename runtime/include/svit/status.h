#pragma once
// Status and Expected<T>: how every svit library function reports bad input.
// No exceptions cross the public API; a failed call returns a Status whose
// message names the file, the element and the offending value.

#include <optional>
#include <string>
#include <utility>

namespace svit {

/// Why an operation failed. Tools map these to exit codes (docs/architecture.md
/// "Command-line contracts": 1 bad input, 2 bad usage, 3 cancelled).
enum class StatusCode {
  kOk = 0,
  kInvalidInput,  ///< malformed or out-of-range data in a file or argument
  kNotFound,      ///< a file, node or element that was named does not exist
  kIoError,       ///< the OS refused to read or write a file
  kUnsupported,   ///< valid input that needs a feature svit does not have
  kCancelled,     ///< a progress callback or stop flag asked to stop
  kInternal,      ///< a GL or library call failed for reasons outside the input
};

/// Name of a status code for messages ("invalid input", ...).
const char* statusCodeName(StatusCode code);

/// Result of an operation with no value. Cheap to copy; `ok()` when no error.
class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status okStatus() { return Status(); }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  /// Human-readable message naming file, element and value; empty when ok.
  const std::string& message() const { return message_; }

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

/// A value or the Status that explains why there is none.
template <typename T>
class Expected {
 public:
  Expected(T value) : value_(std::move(value)) {}          // NOLINT: implicit by design
  Expected(Status status) : status_(std::move(status)) {}  // NOLINT: must not be ok

  bool ok() const { return value_.has_value(); }
  const Status& status() const { return status_; }
  T& value() & { return *value_; }
  const T& value() const& { return *value_; }
  T&& value() && { return std::move(*value_); }
  T* operator->() { return &*value_; }
  const T* operator->() const { return &*value_; }
  T& operator*() & { return *value_; }
  const T& operator*() const& { return *value_; }

 private:
  std::optional<T> value_;
  Status status_;
};

}  // namespace svit
