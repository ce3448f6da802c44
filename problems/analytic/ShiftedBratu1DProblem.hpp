// The 1D Bratu problem with a linear term, u'' + mu u + lambda e^u = 0 on (0, 1), u(0) = u(1) = 0,
// by second-order central differences on n uniform intervals: a two-parameter test problem whose
// fold in lambda moves with mu (the fold curve; mu = 0 is Bratu1DProblem, and the fold's lambda
// falls to 0 as mu rises to the first discrete eigenvalue (4 / h^2) sin^2(pi h / 2)).
// F_i = -(u_{i-1} - 2 u_i + u_{i+1}) / h^2 - mu u_i - lambda e^{u_i}, B = I.
#pragma once

#include <memory>

#include "core/Problem.hpp"
#include "core/Scene.hpp"

namespace keller {

class ShiftedBratu1DProblem final : public Problem {
 public:
  ShiftedBratu1DProblem(int intervals, double lambda, double mu);

  std::string name() const override { return "bratu1d-shifted"; }
  int size() const override { return n_ - 1; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override;
  Status mass_matrix(const Vector& u, SparseMatrix& B) override;
  Vector initial_guess() override { return Vector::Zero(size()); }
  std::vector<std::string> observable_names() const override { return {"u_mid", "u_max"}; }
  Status observables(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  double h() const { return 1.0 / n_; }

  static void declare(SceneSchema& schema);
  static std::unique_ptr<Problem> from_scene(const Scene& scene);

 private:
  int n_;
  ParameterSet params_;
  SparseMatrix pattern_;
};

}  // namespace keller
