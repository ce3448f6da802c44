#include "core/Status.hpp"

namespace keller {

const char* to_string(StatusCode code) {
  switch (code) {
    case StatusCode::Ok: return "ok";
    case StatusCode::NotFinite: return "not-finite";
    case StatusCode::InvalidState: return "invalid-state";
    case StatusCode::SingularMatrix: return "singular-matrix";
    case StatusCode::LinearSolverError: return "linear-solver-error";
    case StatusCode::NotConverged: return "not-converged";
    case StatusCode::Diverged: return "diverged";
    case StatusCode::Interrupted: return "interrupted";
  }
  return "unknown";
}

std::string Status::describe() const {
  std::string s = to_string(code_);
  if (!message_.empty()) s += ": " + message_;
  return s;
}

}  // namespace keller
