// The residual (global Newton) homotopy of a problem: H(u, s) = F(u) - (1 - s) F(u0) = 0, whose
// solution at s = 0 is the guess u0 itself and at s = 1 a solution of F = 0. A problem of the
// interface with one parameter "homotopy" (s in [0, 1]); F's own parameters stay as they are set.
// Continuation in s from u0 reaches F = 0 where Newton from u0 does not (Keller's global homotopy).
#pragma once

#include "core/Problem.hpp"

namespace keller {

class ResidualHomotopy final : public Problem {
 public:
  // F0 = F(u0) is evaluated here; a status where it cannot be (the guess is outside the model's domain).
  ResidualHomotopy(Problem& inner, const Vector& u0);
  const Status& status() const { return status_; }

  std::string name() const override { return "residual homotopy of " + inner_.name(); }
  int size() const override { return inner_.size(); }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return inner_.jacobian_pattern(); }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  // dH/ds = F(u0)
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override;
  Vector initial_guess() override { return u0_; }
  double residual_scale() const override { return inner_.residual_scale(); }
  SolutionFields fields(const Vector& u) const override { return inner_.fields(u); }

 private:
  Problem& inner_;
  Vector u0_, F0_;
  ParameterSet params_;
  Status status_;
};

}  // namespace keller
