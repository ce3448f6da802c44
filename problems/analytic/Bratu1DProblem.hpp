// The 1D Bratu problem u'' + lambda e^u = 0 on (0, 1), u(0) = u(1) = 0, by second-order
// central differences on n uniform intervals: a small algebraic test problem for Newton and
// continuation, with an exact solution u = -2 ln(cosh((x - 1/2) theta / 2) / cosh(theta / 4)),
// theta = sqrt(2 lambda) cosh(theta / 4), and a fold at lambda_c = 3.513830719125.
// F_i = -(u_{i-1} - 2 u_i + u_{i+1}) / h^2 - lambda e^{u_i} (so that B = I, du/dt = -F).
#pragma once

#include <memory>

#include "core/Problem.hpp"
#include "core/Scene.hpp"

namespace keller {

class Bratu1DProblem final : public Problem {
 public:
  Bratu1DProblem(int intervals, double lambda);

  std::string name() const override { return "bratu1d"; }
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

  int intervals() const { return n_; }
  double h() const { return 1.0 / n_; }
  // Exact solution at x on the lower (upper = false) or upper branch; throws if lambda > lambda_c.
  static double exact(double x, double lambda, bool upper);
  static constexpr double kLambdaCritical = 3.513830719125;

  static void declare(SceneSchema& schema);
  static std::unique_ptr<Problem> from_scene(const Scene& scene);

 private:
  int n_;
  ParameterSet params_;
  SparseMatrix pattern_;
};

}  // namespace keller
