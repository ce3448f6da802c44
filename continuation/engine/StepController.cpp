#include "continuation/engine/StepController.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace keller {

namespace {
// A step at the floor that turns by more than the angle limit is passed where its point lies
// within this many steps of the last (a turn of up to 60 degrees puts it within 2).
constexpr double kFloorReach = 2.0;
}  // namespace

StepController::StepController(const StepOptions& options, int target_iterations)
    : options_(options), target_(target_iterations) {
  if (!(options.min > 0 && options.min <= options.max) || target_iterations < 1)
    throw std::invalid_argument("StepController: need 0 < min <= max and a target of at least one iteration");
}

double StepController::first(double requested) const { return std::clamp(requested, options_.min, options_.max); }

double StepController::after_accepted(double ds, const StepOutcome& o) const {
  double next = ds;
  if (o.iterations < target_ && !o.landed)
    next = ds * options_.growth;
  else if (o.iterations > target_ && !o.stale)
    next = ds * options_.slow_shrink;
  return std::clamp(next, options_.min, options_.max);
}

double StepController::angle_limit() const { return options_.max_angle_degrees * M_PI / 180.0; }

double StepController::after_turn(double ds, double angle) const {
  const double limit = angle_limit();
  // (an angle at or below the limit, or not a number, is not a turn rejection: the failure's factor)
  const double factor = angle > limit ? kTurnRetry * limit / angle : options_.shrink;
  return std::max(ds * factor, options_.min);
}

TurnVerdict StepController::judge_turn(double angle, double ds, double distance, bool arclength) const {
  const double limit = angle_limit();
  if (!(angle > limit)) return TurnVerdict::Passed;
  if (ds > options_.min) return arclength ? TurnVerdict::Shorter : TurnVerdict::Jumped;
  // at the floor a turn is passed where the point is the step's own, not one far away
  return arclength && distance > kFloorReach * ds ? TurnVerdict::Far : TurnVerdict::Passed;
}

}  // namespace keller
