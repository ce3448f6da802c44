// An optional capability of a problem beyond core/Problem.hpp: exact second and third directional
// derivatives of F(u, parameters), which the normal forms of located folds, branch points and Hopf
// points need (stability/NormalForms.hpp, through core/HigherDerivatives.hpp). A problem offers
// them by deriving from this class as well as from Problem,
//   class MyProblem final : public Problem, public ExactDerivatives { ... };
// A problem assembled from kernel terms (AssembledProblem) offers them already: nested dual
// numbers through the kernels (core/KernelTerm.hpp). Where a problem does not, the normal forms
// take central differences of its residual, with the accuracy HigherDerivatives states.
#pragma once

#include <vector>

#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

class ExactDerivatives {
 public:
  // A direction: a change of the unknowns and one of the parameters (every parameter of the
  // problem's ParameterSet, in its order); null: no change.
  struct Direction {
    const Vector* u = nullptr;
    const Vector* parameters = nullptr;
  };
  virtual ~ExactDerivatives() = default;
  // Whether this object offers them (an assembled problem: where every term does). Default: yes.
  virtual bool offers_exact_derivatives() const { return true; }
  // out = D^k F(u, p)[d_1, ..., d_k] with k = directions.size(), 2 or 3, at the parameters'
  // present values.
  virtual Status directional_derivative(const Vector& u, const std::vector<Direction>& directions, Vector& out) = 0;
};

}  // namespace keller
