// What every curve of codimension-one points (fold, Hopf, event curves) shares, as the base of
// their augmented problems: unknowns U = (u, p1, extra...), u the inner problem's state, p1 the
// parameter of the branch the point was located on (an unknown of the curve) and the curve's own
// extra unknowns (a Hopf curve's frequency); the inner problem's parameters, with p1 set from U and
// its range checked; the augmented Jacobian's pattern (the inner pattern bordered by dense rows and
// columns), assembled from the bordered form; and derivatives by central differences in a
// parameter and along a direction of the state. (A base class below the AugmentedProblem
// interface: the three curves are augmented problems that differ only in their equations, and
// this is their one shared implementation.)
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "continuation/engine/AugmentedProblem.hpp"
#include "continuation/engine/FixedParameterSolve.hpp"
#include "core/Problem.hpp"

namespace keller {

class CurveProblem : public AugmentedProblem {
 public:
  int size() const override { return n_ + tail_; }
  ParameterSet& parameters() override { return inner_.parameters(); }
  const ParameterSet& parameters() const override { return inner_.parameters(); }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  // The inner problem's pattern where the curve exposes a border (border_size() > 0).
  const SparseMatrix& inner_pattern() const override;
  // The whole augmented Jacobian, assembled from bordered_jacobian().
  Status jacobian(const Vector& U, Vector& F, SparseMatrix& J) override;
  // (dF/dp, the curve's equations' derivative in p) at U for p2 (throws for p1).
  Status parameter_derivative(int p, const Vector& U, Vector& dF) override;
  // The curve turns in p1 where the tangent's p1 part changes sign.
  std::vector<NamedUnknown> turning_unknowns() const override { return {{n_, p1_name()}}; }
  // The inner problem's guess at p1's present value (extra unknowns 0).
  Vector initial_guess() override { return state(inner_.initial_guess(), inner_.parameters().value(p1_)); }
  double residual_scale() const override { return inner_.residual_scale(); }
  SolutionFields fields(const Vector& U) const override { return inner_.fields(U.head(n_)); }

  int p1() const { return p1_; }
  const std::string& p1_name() const { return inner_.parameters().info(p1_).name; }
  // (u, p1, extra) as the curve's state.
  Vector state(const Vector& u, double p1, const Vector& extra = Vector()) const;
  // U corrected at the present parameter values by block elimination (FixedParameterSolve, on
  // `near` where given).
  FixedParameterResult solve_here(Vector& U, const NewtonOptions& newton, const SparseLUOptions& lu,
                                  const StartFactorisation& near = {});

 protected:
  // inner at the point's parameter values; p1: the inner problem's parameter that becomes an
  // unknown; tail: the unknowns after u (p1 and the extra ones, >= 1); what: the curve's name in
  // messages ("fold curve"). Throws where the inner problem has only one parameter.
  CurveProblem(Problem& inner, const std::string& p1, int tail, std::string what);

  // Sets p1 in the inner problem from U; a failure status where it is not finite or out of range.
  Status set_p1(const Vector& U) const;
  // The derivative in the parameter p of the curve's own equations (those after F = 0) at U; sets
  // p1 from U (parameter_derivative adds dF/dp at the same values).
  virtual Status equations_parameter_derivative(int p, const Vector& U, Vector& d) = 0;
  // An empty bordered Jacobian of the curve's structure (K the inner pattern, border `tail`).
  BorderedJacobian blocks() const;
  // d value / d parameter p by central differences (relative step kParameterStep, kept within
  // the parameter's range); the parameter is restored.
  Status parameter_difference(int p, const std::function<Status(Vector&)>& value, Vector& derivative) const;
  // Derivatives of the inner problem along a direction d of its state, by central differences
  // with the step kDirectionStep max(1, |u|) / |d| (max norms): of J (the directional derivative
  // F_uu[d, .], two Jacobians) and of dF/dp (F_pu d, two dF/dp). At the inner problem's present
  // parameter values.
  Status jacobian_along(const Vector& u, const Vector& d, SparseMatrix& D) const;
  Status parameter_derivative_along(int p, const Vector& u, const Vector& d, Vector& D) const;
  // The observables' names: the inner problem's, then p1, then `extra`.
  std::vector<std::string> curve_observable_names(const std::vector<std::string>& extra = {}) const;
  // Whether the curve's analysis (its test function and null vectors) belongs to U at the present
  // parameter values; if not, U and the values are remembered as the analysed ones (the caller
  // then analyses). forget_analysis(): the borders changed, the analysis with them.
  bool analysed_at(const Vector& U);
  void forget_analysis() { analysed_.resize(0); }

  Problem& inner_;
  const int n_;  // the inner problem's unknowns

 private:
  int tail_, p1_;
  std::string what_;
  SparseMatrix pattern_;
  Vector analysed_;
  std::vector<double> analysed_params_;
};

}  // namespace keller
