// A fold of F(u, p1, p2) = 0 continued in a second parameter p2, as an ordinary branch of an
// augmented problem: unknowns (u, p1), equations F = 0 and g = 0, g the minimally augmented test
// function (Govaerts) of the bordered solve [J b; c^T 0] (v, g) = (0, 1), which vanishes exactly
// where J is singular. The Continuation stepper traces it in p2 like any branch of any problem.
#pragma once

#include <memory>
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

// The augmented problem. Its parameters are the inner problem's (the continuation parameter p2
// is one of them; p1 is set from the last unknown by every evaluation). g's derivatives are
// g_z = -w^T J_z v with the adjoint (w, h) of [J^T c; b^T 0] (w, h) = (0, 1): in u by central
// differences of J along v (two Jacobians), in a parameter by central differences of dF/dp along
// v. The borders b, c follow the curve (update_borders: the last w and v, normalised), which
// keeps the bordered matrix regular; g's zero set does not depend on them.
// Observables: the inner problem's, then p1. Monitors: the inner problem's, then "cusp", the
// quadratic coefficient w^T F_uu[v, v] of the fold, whose zero is a cusp point of the curve.
class FoldCurveProblem final : public CurveProblem {
 public:
  // inner at the fold's parameter values; fold_parameter: p1, the parameter of the branch the fold
  // was located on (it becomes an unknown).
  FoldCurveProblem(Problem& inner, const std::string& fold_parameter, SparseLUOptions lu = {});

  std::string name() const override { return inner_.name() + "-fold-curve"; }
  Status residual(const Vector& U, Vector& F) override;
  // [J F_p1; g_u^T g_p1]. J is singular all along a fold curve: no border for block elimination on
  // it (border_size() 0), the augmented Jacobian is factorised whole.
  int border_size() const override { return 0; }
  Status bordered_jacobian(const Vector& U, Vector& F, BorderedJacobian& J) override;
  std::vector<std::string> observable_names() const override { return curve_observable_names(); }
  Status observables(const Vector& U, std::vector<double>& values) override;
  std::vector<std::string> monitor_names() const override;
  Status monitors(const Vector& U, std::vector<double>& values) override;
  std::string summary() const override;

  // Borders from a guess of the null vector (a fold's tangent: its state part; b = c = the guess),
  // refined at U by three bordered solves.
  Status set_borders(const Vector& U, const Vector& null_guess);
  // set_borders, then U corrected by Newton at the present p2 (a located fold is on the curve
  // only to the tolerance it was located to).
  Status start(Vector& U, const Vector& null_guess, const NewtonOptions& newton, SparseLUOptions lu = {});
  // Borders b = w / |w|, c = v / |v| from the bordered solves at U.
  Status update_borders(const Vector& U);
  // The right and left null vectors' approximations v, w and g at U (for tests and output).
  Status null_vectors(const Vector& U, Vector& v, Vector& w, double& g);
  // The quadratic coefficient w^T F_uu[v, v] at U.
  Status quadratic_coefficient(const Vector& U, double& a);

  // Forwards every point to another observer and moves the borders to each accepted point.
  using BorderUpdate = CurveBorderUpdate<FoldCurveProblem>;

 private:
  Status equations_parameter_derivative(int p, const Vector& U, Vector& d) override;
  // F, J, v, w and g at U, computed once per state and parameter values.
  Status analyse(const Vector& U);
  // -w^T (dF/dp)_u v by central differences of dF/dp along v.
  Status parameter_term(int p, const Vector& u, double& gp);

  FoldTestFunction test_;
  Status analysed_status_;  // of the analysis at CurveProblem::analysed_at
  Vector F_;
  SparseMatrix J_;
};

}  // namespace keller
