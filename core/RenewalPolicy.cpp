#include "core/RenewalPolicy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace keller {

double RenewalPolicy::iterations_to_goal(const History& h) {
  const double rate = h.on_this_matrix >= 2 ? std::sqrt(h.residual / h.before_previous) : h.residual / h.previous;
  if (!(rate < 1.0)) return std::numeric_limits<double>::infinity();
  return std::max(0.0, std::log(h.goal / h.residual) / std::log(rate));
}

bool RenewalPolicy::renew(const History& h) const {
  // a damped step says the matrix no longer points the way
  if (!h.full_step) return true;
  const double limit = max_iterations - kChordSpareIterations;
  if (reach_goal) return h.iteration + iterations_to_goal(h) > limit;
  bool renew = !(h.residual <= chord_rate * h.previous);
  if (renew && renewal_cost > 0) {
    const double more = iterations_to_goal(h);
    if (more <= renewal_cost && h.iteration + more <= limit) renew = false;
  }
  if (renew && floor_level > 0 && h.residual <= floor_level) renew = false;
  return renew;
}

}  // namespace keller
