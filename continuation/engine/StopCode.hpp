// Why a branch ended (continuation.stop.*, the step-size floor, a start that failed), for the
// run's result and its exit code.
#pragma once

namespace keller {

enum class StopCode {
  UpperBound,      // reached continuation.upper
  LowerBound,      // reached continuation.lower
  StopObservable,  // the stop observable crossed its threshold
  MaxSteps,        // continuation.max_steps steps made
  StepFloor,       // the step size fell below min_step after failures
  StartFailed,     // the branch could not start (no tangent at the start, no branch to switch to, a
                   // start that cannot be evaluated): no point traced
  Interrupted,     // a signal asked the run to stop
};
const char* to_string(StopCode c);
// Whether the branch ended by a numerical failure (the step floor, a start that failed): its run
// ends with exit code 1 and its file does not replace an existing output.
bool is_failure(StopCode c);

}  // namespace keller
