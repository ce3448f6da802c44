// Why a branch ended (continuation.stop.* and the step-size floor), for the run's result and its
// exit code.
#pragma once

namespace keller {

enum class StopCode {
  UpperBound,      // reached continuation.upper
  LowerBound,      // reached continuation.lower
  StopObservable,  // the stop observable crossed its threshold
  MaxSteps,        // continuation.max_steps steps made
  StepFloor,       // the step size fell below min_step after failures
  Interrupted,     // a signal asked the run to stop
};
const char* to_string(StopCode c);

}  // namespace keller
