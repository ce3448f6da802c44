// A problem with a border: what the continuation engine needs of the augmented problems it builds
// (the curves of folds, Hopf points and events, continuation/curves/) beyond the problem contract
// of core/Problem.hpp. Its Jacobian is an inner sparse matrix K bordered by border_size() dense
// rows and columns (core/BorderedJacobian.hpp: the last border_size() unknowns and equations), so
// that a solver factorises K alone (the inner problem's J) and eliminates the border; and some of
// its unknowns are parameters of the inner problem, whose turns the stepper locates. The engine
// finds it in one place (augmented() and the functions below); a user's problem is a Problem.
#pragma once

#include <string>
#include <vector>

#include "core/BorderedJacobian.hpp"
#include "core/Problem.hpp"

namespace keller {

class AugmentedProblem : public Problem {
 public:
  // The number of border rows and columns to eliminate; 0: none (an augmented problem whose inner
  // matrix is singular all along, as J on a fold curve: its Jacobian is factorised whole).
  virtual int border_size() const = 0;
  // F(u) and the Jacobian in bordered form, K with the pattern inner_pattern() (its border may be
  // wider than border_size() where that is 0).
  virtual Status bordered_jacobian(const Vector& u, Vector& F, BorderedJacobian& J) = 0;
  // F(u) and the border alone (J's B, C and D; K as it was): what a factorisation of K made
  // nearby needs to be used at u. Default: bordered_jacobian, K included.
  virtual Status border(const Vector& u, Vector& F, BorderedJacobian& J) { return bordered_jacobian(u, F, J); }
  // The pattern of K where border_size() > 0; else the Jacobian's own.
  virtual const SparseMatrix& inner_pattern() const = 0;
  // Unknowns that are parameters of the inner problem (a curve's p1): the stepper locates where a
  // branch turns in each (the unknown's part of the tangent changes sign), as it locates folds in
  // the continuation parameter.
  struct NamedUnknown {
    int index = 0;
    std::string name;
  };
  virtual std::vector<NamedUnknown> turning_unknowns() const = 0;
  // Indices of monitors that are not defined everywhere (a Hopf curve's first Lyapunov coefficient,
  // undefined where omega reaches 0 at a Bogdanov-Takens point): NaN there is their value, and no
  // zero is sought on a step with NaN at either end. A NaN of any other monitor fails the point.
  virtual std::vector<int> partial_monitors() const { return {}; }
};

// The problem as an augmented one; null for an ordinary problem.
AugmentedProblem* augmented(Problem& problem);
const AugmentedProblem* augmented(const Problem& problem);
// What the engine asks of any problem: its border size (0 for an ordinary problem), the pattern of
// the matrix a solver factorises (the Jacobian's own for an ordinary problem) and its turning
// unknowns (none for an ordinary problem).
int border_size(const Problem& problem);
const SparseMatrix& inner_pattern(const Problem& problem);
std::vector<AugmentedProblem::NamedUnknown> turning_unknowns(const Problem& problem);
// Its partial monitors (none for an ordinary problem).
std::vector<int> partial_monitors(const Problem& problem);

}  // namespace keller
