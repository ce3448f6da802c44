// Step-size control of the continuation, a pure function of what the last step did: grow by
// `growth` after a corrector that needed fewer than the target iterations, shrink by `slow_shrink`
// after one that needed more, shrink by `shrink` after a failure, within [min, max]; the branch ends
// where a failed step would fall below the floor (a step rejected only for its turn stops at the
// floor instead: the turn is passed there). Also what the turn of the tangent over a step says of
// it (judge_turn).
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

// What the turn of the unit tangent over a step says of the step.
enum class TurnVerdict {
  Passed,   // within the angle limit; or at the floor, where an arclength step's point lies within
            // reach of the last (the step's own), or a natural step's
  Shorter,  // an arclength step turned too sharply (it skipped a feature of the branch): rejected,
            // tried again shorter (after_turn), down to the floor
  Jumped,   // a natural step turned too sharply above the floor (it jumped to another branch past a
            // fold): a failed step (after_failure), not tried shorter as a turn
  Far,      // an arclength step at the floor turned too sharply to a point far away: a failed step
};

// A step retried after a sharp turn aims at this fraction of the angle limit.
inline constexpr double kTurnRetry = 0.75;

class StepController {
 public:
  StepController(const StepOptions& options, int target_iterations);
  // The first step of a branch from a requested size.
  double first(double requested) const;
  // The step after an accepted one of size ds.
  double after_accepted(double ds, const StepOutcome& outcome) const;
  // The step after a failed one of size ds (below min(): the branch ends).
  double after_failure(double ds) const { return ds * options_.shrink; }
  // The step after one rejected only for turning by angle (radians), more than the angle limit:
  // shrunk to turn by kTurnRetry of the limit at the curvature the step showed (the turn grows
  // with the step: ds kTurnRetry limit / angle), but not below the floor, where the angle is not
  // judged (a sharp fold is passed there).
  double after_turn(double ds, double angle) const;
  // A step of size ds whose unit tangents at its ends are angle radians apart and whose point lies
  // distance from the last (arclength norm); arclength: pseudo-arclength, else natural steps.
  TurnVerdict judge_turn(double angle, double ds, double distance, bool arclength) const;
  double min() const { return options_.min; }
  bool below_floor(double ds) const { return ds < options_.min; }
  int target_iterations() const { return target_; }

 private:
  double angle_limit() const;  // max_angle_degrees in radians
  StepOptions options_;
  int target_;
};

}  // namespace keller
