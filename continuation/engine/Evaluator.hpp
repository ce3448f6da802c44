// The continuation engine's access to the problem: the continuation parameter set with its
// admissible range checked, residuals, Jacobians, dF/dp and Jacobian-vector products, each timed
// and counted (where a run's time goes), and the rounding floor of the last assembled Jacobian.
// It finds what a problem offers beyond the contract (a border: AugmentedProblem; gradients:
// MonitorGradients; the pieces of an observable: ObservablePieces) once, where it is built.
#pragma once

#include <functional>
#include <string>

#include "continuation/engine/AugmentedProblem.hpp"
#include "continuation/engine/ObservablePieces.hpp"
#include "core/ConvergenceTest.hpp"
#include "core/MonitorGradients.hpp"
#include "core/Problem.hpp"

namespace keller {

// A function of the branch with its gradient: its value g at (u, lambda) and, where gradient is
// true, its derivatives in u (gu) and in lambda (gl, by differences with step h).
using GradientFunction =
    std::function<Status(const Vector& u, double lambda, double h, bool gradient, double& g, Vector& gu, double& gl)>;

// Where a run's time went (seconds, wall clock): the speed floor is the factorisations.
struct ContinuationTimings {
  double jacobian = 0, parameter_derivative = 0, residual = 0, factorisation = 0, solve = 0, observables = 0,
         output = 0, total = 0, analysis = 0;
  long jacobians = 0, parameter_derivatives = 0, residuals = 0, solves = 0, analyses = 0;
};

class Evaluator {
 public:
  Evaluator(Problem& problem, int parameter, std::string parameter_name);
  Problem& problem() { return problem_; }
  int parameter() const { return p_; }
  const std::string& parameter_name() const { return name_; }
  int size() const { return problem_.size(); }

  // Sets the continuation parameter; a status (not an exception) where it is not finite or
  // outside the problem's admissible range.
  Status set_parameter(double lambda);
  Status residual(const Vector& u, Vector& F);
  // J and F at u (into jacobian_matrix() or, for a problem with a border of its own,
  // bordered_jacobian(); residual_vector()); the rounding floor of J at u.
  Status jacobian(const Vector& u);
  // F and the border of a problem with a border of its own at u, into J (AugmentedProblem::border:
  // K as it was), F into residual_vector(), the rounding floor of that J at u; timed with the
  // Jacobians.
  Status border(const Vector& u, BorderedJacobian& J);
  // The problem's monitor `index` (observable: its observable), minus threshold, with its gradient
  // (MonitorGradients::monitor_gradient, observable_gradient; in lambda by central differences),
  // timed with the observables; null where the problem offers no gradient.
  GradientFunction gradient_function(int index, bool observable, double threshold);
  // Whether the observable is the smallest of smooth pieces (ObservablePieces).
  bool has_pieces(int observable) const { return pieces_ && pieces_->has_pieces(observable); }
  // The piece of such an observable smallest at (u, lambda) (the parameter set there), -1: none.
  Status smallest_piece(int observable, const Vector& u, double lambda, int& piece);
  // One piece of such an observable, minus threshold, with its gradient, as gradient_function.
  GradientFunction piece_function(int observable, int piece, double threshold);
  // The rounding floor of J (made nearby: a factorisation adopted) at u, as if assembled there.
  void set_rounding_floor(const SparseMatrix& J, const Vector& u) { floor_ = keller::rounding_floor(J, u); }
  // dF/dp at u (into parameter_derivative_vector()).
  Status parameter_derivative(const Vector& u);
  // J(u) v by central differences of the residual (two residuals instead of a Jacobian; error
  // about 1e-11 of |J| |v|, below what the tangent iteration asks for).
  Status jacobian_times(const Vector& u, const Vector& v, Vector& out);

  // The last Jacobian as one sparse matrix (a bordered one assembled on the first call).
  const SparseMatrix& jacobian_matrix() const;
  // The problem has a border of its own (AugmentedProblem::border_size() > 0): its Jacobians come
  // in bordered form.
  bool bordered() const { return bordered_; }
  const BorderedJacobian& bordered_jacobian() const { return JB_; }
  const Vector& residual_vector() const { return F_; }
  const Vector& parameter_derivative_vector() const { return Fp_; }
  // rounding_floor() (ConvergenceTest) of the last assembled Jacobian at its point.
  double rounding_floor() const { return floor_; }
  ContinuationTimings& timings() { return timings_; }

 private:
  // A function of the state alone and its gradient in u, as a GradientFunction minus threshold.
  using StateValue = std::function<Status(const Vector& u, double& value)>;
  using StateGradient = std::function<Status(const Vector& u, Vector& gradient)>;
  GradientFunction timed_function(StateValue value, StateGradient gradient_in_u, double threshold);

  Problem& problem_;
  int p_;
  std::string name_;
  AugmentedProblem* augmented_;  // what the problem offers beyond the contract (null: nothing)
  MonitorGradients* gradients_;
  ObservablePieces* pieces_;
  bool bordered_;
  // J_ holds the whole Jacobian; for a bordered problem JB_ does, J_ once assembled (assembled_)
  mutable SparseMatrix J_;
  mutable bool assembled_ = true;
  BorderedJacobian JB_;
  Vector F_, Fp_, plus_, minus_;
  double floor_ = 0.0;
  ContinuationTimings timings_;
};

}  // namespace keller
