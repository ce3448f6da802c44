#include "core/ConvergenceTest.hpp"

#include <algorithm>
#include <cmath>

namespace keller {

double rounding_floor(const SparseMatrix& J, const Vector& u) {
  Vector row(J.rows());
  row.setZero();
  for (int c = 0; c < J.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(J, c); it; ++it) row[it.row()] += std::abs(it.value() * u[c]);
  return std::numeric_limits<double>::epsilon() * (row.size() ? row.maxCoeff() : 0.0);
}

double ConvergenceTest::floor_level() const { return std::max(kRoundingFloorBand * tolerance, problem_floor); }

void ConvergenceTest::aim_at_floor(double neighbours_floor) {
  goal = std::min(std::max(neighbours_floor, problem_floor), floor_level());
}

ConvergenceTest::Verdict ConvergenceTest::judge(const Iterate& it) const {
  if (it.residual <= aim()) return Verdict::Converged;
  // above the floor level a residual is the iteration's, not rounding
  if (!(it.residual <= floor_level())) return Verdict::Continue;
  // an update at rounding level, counting the steps still to come at the iteration's rate: the
  // iterate cannot move further
  const bool still = std::isfinite(it.update) && it.contraction < 1.0 &&
                     it.update / (1.0 - it.contraction) <= update_tolerance * it.scale;
  // a residual that stopped falling, near the smallest one the iteration reached (one far above
  // that is growing)
  const bool stalled = it.residual > kStallRatio * it.previous &&
                       (!slow || it.residual > kSlowStallRatio * it.before_previous) &&
                       !(it.residual > kFloorWander * it.best);
  return still || stalled ? Verdict::RoundingFloor : Verdict::Continue;
}

}  // namespace keller
