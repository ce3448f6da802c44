// A Hopf point of F(u, p1, p2) = 0 continued in a second parameter p2, as an ordinary branch of an
// augmented problem: unknowns (u, p1, omega), equations F = 0 and the real and imaginary parts of
// the minimally augmented complex test function g (Govaerts; as LOCA's and BifurcationKit's Hopf
// continuation) of the bordered solve
//   [ J - i omega B   b ] [v]   [0]
//   [ c^H             0 ] [g] = [1],
// which vanishes exactly where J - i omega B is singular: where i omega is an eigenvalue of
// J phi = sigma B phi (B du/dt = -F), a pair of eigenvalues on the imaginary axis. The Continuation
// stepper traces it in p2 like any branch, eliminating the border on J's factorisation.
#pragma once

#include <complex>
#include <functional>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "continuation/curves/CurveBorderUpdate.hpp"
#include "continuation/curves/CurveProblem.hpp"
#include "continuation/curves/FoldTestFunction.hpp"
#include "core/Newton.hpp"
#include "core/Problem.hpp"
#include "core/SparseLU.hpp"

namespace keller {

using ComplexVector = Eigen::VectorXcd;

// The augmented problem. g's derivatives are g_z = -w^H (J - i omega B)_z v with the adjoint (w, h)
// of the conjugate-transposed bordered matrix: in u by central differences of J along Re v and
// Im v (four Jacobians; the dependence of B on u is left out, exact where B is constant), in a
// parameter by central differences of dF/dp along v and of B in the parameter, in omega exactly
// (g_omega = i w^H B v). The complex system is solved in its real form of size 2n + 2. The borders
// follow the curve (update_borders: the last w and v, normalised), which keeps the bordered
// matrix regular; g's zero set does not depend on them.
// Observables: the inner problem's, then p1 and omega. Monitors: the inner problem's, then the
// codimension-two test functions "bogdanov-takens" (omega itself: the pair meets at zero, where the
// Hopf curve ends on a fold curve) and "fold-hopf" (the fold test function of J, whose zero is a
// real eigenvalue through zero while the pair sits on the imaginary axis), and, where a first
// Lyapunov coefficient is given (set_lyapunov_coefficient), "bautin": l1 at the point, whose zero
// is a Bautin (generalised Hopf) point, where the Hopf bifurcation turns from super- to
// subcritical.
class HopfCurveProblem final : public CurveProblem {
 public:
  // inner at the Hopf point's parameter values; hopf_parameter: p1, the parameter of the branch the
  // Hopf point was located on (it becomes an unknown). The inner problem needs a mass matrix.
  HopfCurveProblem(Problem& inner, const std::string& hopf_parameter, SparseLUOptions lu = {});

  std::string name() const override { return inner_.name() + "-hopf-curve"; }
  Status residual(const Vector& U, Vector& F) override;
  // [J F_p1 0; Re g_u^T Re g_p1 Re g_omega; Im g_u^T Im g_p1 Im g_omega]: J bordered by two columns
  // and rows.
  int border_size() const override { return 2; }
  Status bordered_jacobian(const Vector& U, Vector& F, BorderedJacobian& J) override;
  std::vector<std::string> observable_names() const override { return curve_observable_names({"omega"}); }
  Status observables(const Vector& U, std::vector<double>& values) override;
  std::vector<std::string> monitor_names() const override;
  Status monitors(const Vector& U, std::vector<double>& values) override;
  std::string summary() const override;

  // (u, p1, omega) as the augmented state.
  Vector state(const Vector& u, double p1, double omega) const;
  // Borders from a guess of the critical eigenvector (a Hopf point's mode; b = c = the guess, or a
  // generic vector where it is empty), refined at U by bordered solves; the fold-Hopf test
  // function's borders likewise, from a generic vector.
  Status set_borders(const Vector& U, const ComplexVector& mode_guess);
  // set_borders, then U corrected by Newton at the present p2 (block elimination on J).
  Status start(Vector& U, const ComplexVector& mode_guess, const NewtonOptions& newton, SparseLUOptions lu = {});
  // Borders b = w / |w|, c = v / |v| from the bordered solves at U (and the fold-Hopf function's).
  Status update_borders(const Vector& U);
  // The eigenvector's and the adjoint's approximations v, w and g at U.
  Status null_vectors(const Vector& U, ComplexVector& v, ComplexVector& w, std::complex<double>& g);

  // Forwards every point to another observer and moves the borders to each accepted point.
  using BorderUpdate = CurveBorderUpdate<HopfCurveProblem>;

  // The first Lyapunov coefficient of the inner problem at a Hopf point: (inner at the point's
  // parameter values, p1's index, u, omega, an approximation of the critical eigenvector) -> l1.
  // It is computed outside continuation/ (the normal forms): the curve only monitors its sign. The
  // value should be smooth along the curve (l1 of an eigenvector of fixed norm, not of its
  // largest entry), so that the zero is located by the secant steps of any monitor.
  using LyapunovCoefficient = std::function<Status(Problem& inner, int p1, const Vector& u, double omega,
                                                   const ComplexVector& mode, double& l1)>;
  // Adds the monitor "bautin" (after "fold-hopf"); an empty function removes it. It changes
  // monitor_names(): call it before the curve is given to a Continuation.
  void set_lyapunov_coefficient(LyapunovCoefficient l1) { l1_ = std::move(l1); }
  // "bautin", where it is monitored: NaN where the normal form cannot be computed.
  std::vector<int> partial_monitors() const override;

 private:
  Status equations_parameter_derivative(int p, const Vector& U, Vector& d) override;
  // F, J, B, v, w and g at U, computed once per state and parameter values.
  Status analyse(const Vector& U);
  // The real form of [J - i omega B, b; c^H, 0] (size 2n + 2).
  SparseMatrix real_form(const SparseMatrix& J, const SparseMatrix& B, double omega) const;
  // -w^H (J - i omega B)_p v by central differences of dF/dp along v and of B in p.
  Status parameter_term(int p, const Vector& u, double omega, std::complex<double>& gp);

  ComplexVector b_, c_;
  LyapunovCoefficient l1_;
  SparseLU lu_;
  FoldTestFunction fold_;
  Status analysed_status_;  // of the analysis at CurveProblem::analysed_at
  Vector F_;
  SparseMatrix J_, B_;
  ComplexVector v_, w_;
  std::complex<double> g_;
};

}  // namespace keller
