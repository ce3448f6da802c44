// The 1D pitchfork problem u'' + lambda u - u^3 + eps = 0 on (0, 1), u(0) = u(1) = 0, by
// second-order central differences on n uniform intervals (unknowns: the n - 1 interior values):
// a small algebraic test problem for branch points and linear stability. For eps = 0 the
// trivial branch u = 0 has simple branch points (supercritical pitchforks) at the eigenvalues of
// the discrete Laplacian, lambda_k = (4 / h^2) sin^2(k pi h / 2) -> (k pi)^2, where the mode
// sin(k pi x) bifurcates; eps != 0 breaks the symmetry u -> -u and unfolds the first: the branch from
// small lambda then passes lambda_1 smoothly into the sin(pi x)-like solution.
// F_i = -(u_{i-1} - 2 u_i + u_{i+1}) / h^2 - lambda u_i + u_i^3 - eps, B = I (du/dt = -F), so
// u = 0 is stable (all sigma > 0) for lambda < lambda_1 and gains one unstable mode at each lambda_k.
#pragma once

#include <memory>

#include "core/Problem.hpp"
#include "core/Scene.hpp"

namespace keller {

class Pitchfork1DProblem final : public Problem {
 public:
  // Parameters: "lambda" (index 0) and the imperfection "eps" (index 1). Throws if intervals < 2.
  Pitchfork1DProblem(int intervals, double lambda, double eps = 0.0);

  std::string name() const override { return "pitchfork1d"; }
  int size() const override { return n_ - 1; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override;
  Status mass_matrix(const Vector& u, SparseMatrix& B) override;
  // u = 0: the trivial solution for eps = 0 (Newton's start otherwise).
  Vector initial_guess() override { return Vector::Zero(size()); }
  // u(1/2) (zero on the branches of the even modes k = 2, 4, ...), u(1/4) (sees k = 1, 2, 3),
  // the discrete L2 norm sqrt(h sum u_i^2) and the largest grid value; u(x) between grid nodes
  // is linearly interpolated.
  std::vector<std::string> observable_names() const override { return {"u_mid", "u_quarter", "u_norm", "u_max"}; }
  Status observables(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  int intervals() const { return n_; }
  double h() const { return 1.0 / n_; }
  // The k-th branch point of the trivial branch on this grid, (4 / h^2) sin^2(k pi h / 2).
  static double branch_point(int k, int intervals);

  static void declare(SceneSchema& schema);
  static std::unique_ptr<Problem> from_scene(const Scene& scene);

 private:
  double value_at(const Vector& u, double x) const;
  int n_;
  ParameterSet params_;
  SparseMatrix pattern_;
};

}  // namespace keller
