#include "continuation/engine/AugmentedProblem.hpp"

namespace keller {

AugmentedProblem* augmented(Problem& problem) { return dynamic_cast<AugmentedProblem*>(&problem); }

const AugmentedProblem* augmented(const Problem& problem) { return dynamic_cast<const AugmentedProblem*>(&problem); }

int border_size(const Problem& problem) {
  const AugmentedProblem* a = augmented(problem);
  return a ? a->border_size() : 0;
}

const SparseMatrix& inner_pattern(const Problem& problem) {
  const AugmentedProblem* a = augmented(problem);
  return a ? a->inner_pattern() : problem.jacobian_pattern();
}

std::vector<AugmentedProblem::NamedUnknown> turning_unknowns(const Problem& problem) {
  const AugmentedProblem* a = augmented(problem);
  return a ? a->turning_unknowns() : std::vector<AugmentedProblem::NamedUnknown>{};
}

std::vector<int> partial_monitors(const Problem& problem) {
  const AugmentedProblem* a = augmented(problem);
  return a ? a->partial_monitors() : std::vector<int>{};
}

}  // namespace keller
