// Step-size control of the continuation, a pure function of what the last step did: grow by
// `growth` after a corrector that needed fewer than the target iterations, shrink by `slow_shrink`
// after one that needed more, shrink by `shrink` after a failure, within [min, max]; the branch ends
// where a failed step would fall below the floor (a step rejected only for its turn stops at the
// floor instead: the turn is passed there).
#pragma once

#include <algorithm>

#include "continuation/engine/ContinuationOptions.hpp"

namespace keller {

struct StepOutcome {
  int iterations = 0;  // corrector iterations of the accepted step
  // the corrector kept an old factorisation and needed more iterations than the target without
  // renewing it: the step was not too long, the matrix was old (not shrunk)
  bool stale = false;
  // the step was shortened to land on a stop or a bound: it says nothing for a longer one (not grown)
  bool landed = false;
};

class StepController {
 public:
  StepController(const StepOptions& options, int target_iterations);
  // The first step of a branch from a requested size.
  double first(double requested) const;
  // The step after an accepted one of size ds.
  double after_accepted(double ds, const StepOutcome& outcome) const;
  // The step after a failed one of size ds (below min(): the branch ends).
  double after_failure(double ds) const { return ds * options_.shrink; }
  // The step after one rejected only for turning by more than the angle limit: shrunk, but not
  // below the floor, where the angle is not judged (a sharp fold is passed there).
  double after_turn(double ds) const { return std::max(ds * options_.shrink, options_.min); }
  double min() const { return options_.min; }
  bool below_floor(double ds) const { return ds < options_.min; }
  int target_iterations() const { return target_; }

 private:
  StepOptions options_;
  int target_;
};

}  // namespace keller
