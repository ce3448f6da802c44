// Status of a numerical evaluation. Numerical failure (a NaN, an inverted element, a singular
// matrix, a Newton iteration that does not converge) is reported as a Status that callers
// react to; exceptions are reserved for misuse and bad configuration.
#pragma once

#include <string>
#include <utility>

namespace keller {

enum class StatusCode {
  Ok = 0,
  NotFinite,          // NaN or Inf in a residual, Jacobian or solution
  InvalidState,       // the state is outside the model's domain (inverted element, tr M >= 3b, ...)
  SingularMatrix,     // the linear solver found a (numerically) singular matrix
  LinearSolverError,  // any other failure of the linear solver (out of memory, ...)
  NotConverged,       // an iteration hit its limit without converging
  Diverged,           // an iteration grew instead of converging
  Interrupted,        // the user asked to stop
};

const char* to_string(StatusCode code);

class Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status ok() { return {}; }
  bool is_ok() const { return code_ == StatusCode::Ok; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // "not-finite: residual has NaN in row 12"
  std::string describe() const;

 private:
  StatusCode code_ = StatusCode::Ok;
  std::string message_;
};

}  // namespace keller
