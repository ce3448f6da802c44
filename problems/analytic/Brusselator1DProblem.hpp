// The Brusselator reaction-diffusion system on (0, L) with no-flux boundaries,
//   u_t = D_u u_xx + a - (b + 1) u + u^2 v,   v_t = D_v v_xx + b u - u^2 v,
// by second-order central differences on the n + 1 nodes x_i = i L / n, boundaries included,
// with ghost-point Neumann conditions (u_{-1} = u_1, u_{n+1} = u_{n-1}): a small algebraic test
// problem for Hopf bifurcations. Unknowns interleaved per node: (u_0, v_0, u_1, v_1, ...).
// F = -(right-hand side) and B = I (du/dt = -F). The uniform state (u, v) = (a, b / a) is an exact
// solution for all parameters; constants are exact eigenvectors of the discrete Laplacian, so its
// k = 0 mode loses stability through a Hopf bifurcation at b = 1 + a^2 with frequency a exactly,
// on every grid. With D_u = D_v = D the linearisation on mode k is that on k = 0 shifted by
// D mu_k (mu_k > 0 the eigenvalues of the discrete -d^2/dx^2), so there is no Turing instability
// and this Hopf is the first instability of the uniform branch.
#pragma once

#include <memory>

#include "core/Problem.hpp"
#include "core/Scene.hpp"

namespace keller {

struct Brusselator1DOptions {
  int intervals = 64;   // n, grid intervals (n + 1 nodes)
  double length = 1.0;  // L
  double a = 2.0;       // feed rate; the uniform state is (a, b / a)
  double b = 3.0;       // conversion rate; Hopf of the uniform state at b = 1 + a^2
  double D_u = 1.0;     // diffusivities
  double D_v = 1.0;

  static void declare(SceneSchema& schema);
  static Brusselator1DOptions from_scene(const Scene& scene);
};

class Brusselator1DProblem final : public Problem {
 public:
  // Parameters "a", "b", "D_u", "D_v" (indices 0..3). Throws on intervals < 2, length <= 0,
  // a <= 0 or negative b, D_u, D_v.
  explicit Brusselator1DProblem(const Brusselator1DOptions& options);

  std::string name() const override { return "brusselator1d"; }
  int size() const override { return 2 * (n_ + 1); }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override;
  Status mass_matrix(const Vector& u, SparseMatrix& B) override;
  // The uniform steady state (a, b / a) at the current parameters.
  Vector initial_guess() override;
  // Means over (0, L) by the trapezoidal rule (the quadrature the ghost-point scheme conserves)
  // and the extreme nodal values of u.
  std::vector<std::string> observable_names() const override { return {"u_mean", "v_mean", "u_max", "u_min"}; }
  Status observables(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  int intervals() const { return n_; }
  double h() const { return length_ / n_; }

  static std::unique_ptr<Problem> from_scene(const Scene& scene);

 private:
  // Discrete second derivative of component c (0: u, 1: v) at node i, ghost-point Neumann ends.
  double laplacian(const Vector& w, int c, int i) const;
  int n_;
  double length_;
  ParameterSet params_;
  SparseMatrix pattern_;
};

}  // namespace keller
