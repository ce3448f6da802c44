#include "runs/FloquetAnalysis.hpp"

#include <algorithm>

namespace keller {

FloquetAnalysis FloquetAnalysis::for_branch(int multipliers) {
  FloquetOptions o;
  o.count = std::max(multipliers, kLeast);
  return FloquetAnalysis(o);
}

Status FloquetAnalysis::compute(int n, const std::function<Status(const Vector&, Vector&)>& M,
                                std::vector<std::complex<double>>& values, int& trivial,
                                std::vector<Eigen::VectorXcd>* vectors, MultiplierAccuracy accuracy) {
  FloquetOptions o = options_;
  if (accuracy.tolerance > 0.0) o.tolerance = accuracy.tolerance;
  o.circle_share = accuracy.circle_share;
  o.vectors = vectors != nullptr;
  o.start = last_.ritz;  // the last orbit's directions: a neighbour's, on a branch
  const Status st = floquet_multipliers(n, M, o, last_);
  values = last_.multipliers;
  trivial = last_.trivial;
  if (vectors) *vectors = last_.vectors;
  return st;
}

}  // namespace keller
