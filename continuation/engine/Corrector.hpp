// The corrector of the continuation: solves the extended system F(u, lambda) = 0, N(u, lambda) = 0
// (N a linear constraint: the pseudo-arclength row or lambda = value) from a prediction, by
// Newton or by the chord on a kept factorisation with Anderson mixing, renewing the factorisation
// where the renewal policy asks (RenewalPolicy, shared with core's Newton), stopping where the
// convergence test says (ConvergenceTest, shared too), and rejecting at once a step whose Newton
// iteration leaves Newton's region of contraction (Deuflhard's monotonicity test). Returns what
// happened as a result, and tells the shared factorisation how the correction ended (ReusePolicy:
// whether the next one may start on it); keeps no state between calls.
#pragma once

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "continuation/engine/KeptFactorisation.hpp"
#include "core/Newton.hpp"

namespace keller {

struct CorrectorResult {
  Status status;
  int iterations = 0;              // corrector iterations (solves of the extended system)
  double residual = 0.0;           // |F|_inf where it stopped
  bool refactored = false;         // a factorisation was made (its first iteration's, or a renewal)
  bool at_rounding_floor = false;  // converged at the problem's rounding floor, above the tolerance
};

class Corrector {
 public:
  // What is corrected: a continuation step, or a point located between two converged ones (whose
  // chord on a kept factorisation goes on while it reaches its goal before the limit, and is
  // retried once from the prediction on a fresh factorisation where it fails).
  enum class Kind { Step, Located };

  Corrector(Evaluator& ev, KeptFactorisation& kept, const ArclengthNorm& norm, const ContinuationOptions& options,
            const NewtonOptions& newton);

  // Corrects (u, lambda) in place under constraint c. floor: the rounding floor the neighbouring
  // points reached (residual_floor() of their residuals; 0: none), the goal of a slow chord where
  // the tolerance lies below it.
  CorrectorResult correct(Vector& u, double& lambda, const Constraint& c, Kind kind, double floor = 0.0);
  // The residual tolerance (absolute, max norm).
  double tolerance() const;
  // The rounding floor two neighbouring points show: twice their larger residual where that is
  // above the tolerance (they stopped at rounding there), else 0.
  double residual_floor(double r0, double r1) const;
  // The renewal cost in use: the option, or measured along the run (0 before anything is measured).
  double renewal_cost() const;

 private:
  CorrectorResult iterate(Vector& u, double& lambda, const Constraint& c, Kind kind, double floor);
  Evaluator& ev_;
  KeptFactorisation& kept_;
  const ArclengthNorm& norm_;
  const ContinuationOptions& options_;
  NewtonOptions newton_;
  Vector F_, du_;
};

}  // namespace keller
