#include "continuation/events/BranchSwitcher.hpp"

#include <cmath>

namespace keller {

Status branch_direction(Evaluator& ev, const SparseLUOptions& lu_options, const ArclengthNorm& norm,
                        const BranchPoint& bp, int direction, Vector& tu, double& tl) {
  Status st = ev.set_parameter(bp.lambda);
  if (st.is_ok()) st = ev.jacobian(bp.u);
  if (!st.is_ok()) return st;
  SparseLU lu(lu_options);
  st = lu.factorize(ev.jacobian_matrix());
  if (!st.is_ok()) return {st.code(), "J at the branch point: " + st.message()};
  Vector phi(ev.size());
  for (int i = 0; i < phi.size(); ++i) phi[i] = std::sin(1.0 + 0.7 * i);  // deterministic, generic
  phi /= phi.norm();
  for (int it = 0; it < kNullVectorMaxIterations; ++it) {
    Vector y;
    st = lu.solve(phi, y);
    if (!st.is_ok()) return st;
    y /= y.norm();
    if (y.dot(phi) < 0) y = -y;  // a negative eigenvalue flips the sign at every step
    const double change = (y - phi).norm();
    phi = y;
    if (change < kNullVectorTolerance) break;
  }
  // a fixed sign: the entry of largest magnitude positive (direction +1 makes it grow)
  Eigen::Index imax = 0;
  phi.cwiseAbs().maxCoeff(&imax);
  if (phi[imax] < 0) phi = -phi;
  const double along = norm.dot(phi, 0.0, bp.tu, bp.tlambda);
  Vector t = phi - along * bp.tu;
  double l = -along * bp.tlambda;
  const double nrm = norm.norm(t, l);
  if (!(nrm > 0) || !std::isfinite(nrm)) return {StatusCode::InvalidState, "the null vector of J is the old tangent"};
  const double sign = direction >= 0 ? 1.0 : -1.0;
  tu = (sign / nrm) * t;
  tl = sign * l / nrm;
  return {};
}

}  // namespace keller
