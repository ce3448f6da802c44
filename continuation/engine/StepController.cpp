#include "continuation/engine/StepController.hpp"

#include <algorithm>
#include <stdexcept>

namespace keller {

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

}  // namespace keller
