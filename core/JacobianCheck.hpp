// A problem's derivatives against central differences of its residual: J v for random directions
// v, and dF/dp for each parameter, at a state and at a random state near it (where a state makes
// some terms vanish, u = 0 for a cubic, the perturbed one does not). What `solve
// --check-jacobian` reports, so that a user's hand-written or AD Jacobian is checked before it is
// trusted.
//
// The directions are v_i = r_i (1 + |u_i|), r_i uniform in [-1, 1]: each unknown moves relative
// to its own size. The error of a direction is |J v - D_h v|_inf / max(|J v|_inf, |D_h v|_inf), with
// D_h v = (F(u + h v) - F(u - h v)) / 2h (for dF/dp: steps h max(1, |p|), one-sided at the end of
// p's range): O(h^2) truncation and O(eps |F| / h) rounding, 1e-12 to 1e-8 for an
// exact Jacobian (the latter where |F| is 1e3 times the derivative); a wrong entry gives its share
// of J v, 1e-5 and more for any that matters (tests/unit/JacobianCheckTest.cpp). The error is the
// smallest over the steps h = 1e-4 ... 1e-7 (the balance of truncation and rounding depends on the
// problem; a wrong derivative keeps its error at every step), and that of dF/dp is relative to at
// least 1e-6 of |J v|_inf / max(1, |p|): a parameter that hardly moves F (beta of a fluid at rest)
// is not judged by its rounding.
#pragma once

#include <string>
#include <vector>

#include "core/Problem.hpp"

namespace keller {

struct JacobianCheckOptions {
  int directions = 4;         // random directions per state
  double perturbation = 0.1;  // the second state: u + perturbation v, v a random direction (below)
  double tolerance = 1e-6;    // an error above it fails the check
  unsigned seed = 1;          // of the random directions (the check is repeatable)
};

struct JacobianCheckResult {
  Status status;                         // a residual, Jacobian or dF/dp that failed to evaluate
  std::vector<std::string> states;       // "the state", "the state perturbed by 1e-01"
  std::vector<double> state_errors;      // per state: the largest error over the directions
  std::vector<std::string> parameters;   // the parameters' names
  std::vector<double> parameter_errors;  // per parameter: the largest error of dF/dp over the states
  std::vector<bool> parameter_checked;   // false for a parameter without room for a difference in
                                         // its range (Re = 0 of a Stokes run): no dF/dp, error 0
  bool passed(double tolerance) const;   // status ok and every error at most tolerance
  std::string describe() const;          // a few lines for the terminal
};

// Leaves the problem's parameters as they were. A perturbed state outside the problem's domain
// (residual: InvalidState) is tried closer, by factors of 10 down to 1e-4 of the perturbation, then
// left out.
JacobianCheckResult check_jacobian(Problem& problem, const Vector& u, const JacobianCheckOptions& options = {});

}  // namespace keller
