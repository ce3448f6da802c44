// What every curve of codimension-one points (fold, Hopf, event curves) shares: its unknowns
// U = (u, p1, extra...), u the inner problem's state, p1 the parameter of the branch the point was
// located on (an unknown of the curve) and the curve's own extra unknowns (a Hopf curve's
// frequency); p1 set in the inner problem from U with its range checked; the augmented Jacobian's
// pattern (the inner pattern bordered by dense rows and columns); and derivatives in a parameter
// by central differences within its range. The curves hold one (composition, not a base class).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/Problem.hpp"

namespace keller {

class CurveUnknowns {
 public:
  // inner at the point's parameter values; p1: the inner problem's parameter that becomes an
  // unknown; border: the unknowns after u (p1 and the extra ones, >= 1); what: the curve's name
  // in messages ("fold curve"). Throws where the inner problem has only one parameter.
  CurveUnknowns(Problem& inner, const std::string& p1, int border, std::string what);

  Problem& inner() const { return inner_; }
  int inner_size() const { return n_; }
  int border() const { return border_; }
  int size() const { return n_ + border_; }
  int p1() const { return p1_; }
  const std::string& p1_name() const { return inner_.parameters().info(p1_).name; }
  const std::string& what() const { return what_; }
  // (u, p1, extra) as the curve's state.
  Vector state(const Vector& u, double p1, const Vector& extra = Vector()) const;
  // Sets p1 in the inner problem from U; a failure status where it is not finite or out of range.
  Status set_p1(const Vector& U) const;
  // The augmented Jacobian's pattern: the inner pattern bordered by `border` dense columns and rows.
  const SparseMatrix& pattern() const { return pattern_; }
  // An empty bordered Jacobian of the curve's structure (for problems to fill).
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
  // The turning unknowns of Problem::turning_unknowns(): p1.
  std::vector<Problem::NamedUnknown> turning_unknowns() const { return {{n_, p1_name()}}; }
  // The observables' names: the inner problem's, then p1, then `extra`.
  std::vector<std::string> observable_names(const std::vector<std::string>& extra = {}) const;

 private:
  Problem& inner_;
  int n_, border_, p1_;
  std::string what_;
  SparseMatrix pattern_;
};

}  // namespace keller
