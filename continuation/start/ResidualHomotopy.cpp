#include "continuation/start/ResidualHomotopy.hpp"

namespace keller {

ResidualHomotopy::ResidualHomotopy(Problem& inner, const Vector& u0) : inner_(inner), u0_(u0) {
  params_.add("homotopy", 0.0, "s: H(u, s) = F(u) - (1 - s) F(u0)", 0.0, 1.0);
  status_ = inner_.residual(u0_, F0_);
}

Status ResidualHomotopy::residual(const Vector& u, Vector& F) {
  const Status st = inner_.residual(u, F);
  if (st.is_ok()) F -= (1.0 - params_.value(0)) * F0_;
  return st;
}

Status ResidualHomotopy::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  const Status st = inner_.jacobian(u, F, J);
  if (st.is_ok()) F -= (1.0 - params_.value(0)) * F0_;
  return st;
}

Status ResidualHomotopy::parameter_derivative(int, const Vector&, Vector& dF) {
  dF = F0_;
  return {};
}

}  // namespace keller
