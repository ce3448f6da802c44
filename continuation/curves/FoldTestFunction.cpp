#include "continuation/curves/FoldTestFunction.hpp"

#include <cmath>
#include <stdexcept>

#include "core/BorderedJacobian.hpp"

namespace keller {

FoldTestFunction::FoldTestFunction(int n, SparseLUOptions lu)
    : n_(n), b_(Vector::Zero(n)), c_(Vector::Zero(n)), lu_(lu) {}

void FoldTestFunction::set_borders(const Vector& null_guess) {
  if (null_guess.size() != n_) throw std::invalid_argument("fold test function: null vector guess of the wrong size");
  const double nn = null_guess.norm();
  if (!(nn > 0.0)) throw std::invalid_argument("fold test function: the null vector guess vanishes");
  c_ = null_guess / nn;
  b_ = c_;
}

Status FoldTestFunction::evaluate(const SparseMatrix& J) {
  BorderedJacobian M;
  M.K = J;
  M.B = b_;
  M.C = c_;
  M.D = Matrix::Zero(1, 1);
  Status st = lu_.factorize(M.assembled());
  if (!st.is_ok()) return st;
  Vector rhs = Vector::Zero(n_ + 1), x;
  rhs[n_] = 1.0;
  st = lu_.solve(rhs, x);
  if (!st.is_ok()) return st;
  v_ = x.head(n_);
  g_ = x[n_];
  det_sign_ = lu_.determinant_sign();
  st = lu_.solve(rhs, x, true);
  if (!st.is_ok()) return st;
  w_ = x.head(n_);
  if (!std::isfinite(g_) || !v_.allFinite() || !w_.allFinite())
    return {StatusCode::NotFinite, "the bordered solve for the fold test function is not finite"};
  return {};
}

Status FoldTestFunction::update_borders() {
  const double vn = v_.norm(), wn = w_.norm();
  if (!(vn > 0.0) || !(wn > 0.0)) return {StatusCode::SingularMatrix, "fold test function: a null vector vanished"};
  c_ = v_ / vn;
  b_ = w_ / wn;
  return {};
}

}  // namespace keller
