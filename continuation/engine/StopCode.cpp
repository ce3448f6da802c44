#include "continuation/engine/StopCode.hpp"

namespace keller {

const char* to_string(StopCode c) {
  switch (c) {
    case StopCode::UpperBound: return "upper-bound";
    case StopCode::LowerBound: return "lower-bound";
    case StopCode::StopObservable: return "stop-observable";
    case StopCode::MaxSteps: return "max-steps";
    case StopCode::StepFloor: return "step-floor";
    case StopCode::StartFailed: return "start-failed";
    case StopCode::Interrupted: return "interrupted";
  }
  return "?";
}

bool is_failure(StopCode c) { return c == StopCode::StepFloor || c == StopCode::StartFailed; }

}  // namespace keller
