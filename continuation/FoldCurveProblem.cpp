#include "continuation/FoldCurveProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

namespace {

std::vector<double> parameter_values(const ParameterSet& ps) { return {ps.values(), ps.values() + ps.size()}; }

}  // namespace

FoldCurveProblem::FoldCurveProblem(Problem& inner, const std::string& fold_parameter, SparseLUOptions lu)
    : inner_(inner), n_(inner.size()), p1_(inner.parameters().index(fold_parameter)), lu_(lu) {
  if (inner_.parameters().size() < 2)
    throw std::invalid_argument("fold curve of '" + inner_.name() + "': the problem has only one parameter");
  b_ = Vector::Zero(n_);
  c_ = Vector::Zero(n_);
  pattern_ = bordered(inner_.jacobian_pattern(), Vector::Zero(n_), Vector::Zero(n_), 0.0);
}

SparseMatrix FoldCurveProblem::bordered(const SparseMatrix& A, const Vector& col, const Vector& row,
                                        double corner) const {
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(A.nonZeros() + 2 * n_ + 1);
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) t.emplace_back(it.row(), j, it.value());
  for (int i = 0; i < n_; ++i) {
    t.emplace_back(i, n_, col[i]);
    t.emplace_back(n_, i, row[i]);
  }
  t.emplace_back(n_, n_, corner);
  SparseMatrix M(n_ + 1, n_ + 1);
  M.setFromTriplets(t.begin(), t.end());
  M.makeCompressed();
  return M;
}

Vector FoldCurveProblem::state(const Vector& u, double p1) const {
  Vector U(n_ + 1);
  U.head(n_) = u;
  U[n_] = p1;
  return U;
}

Vector FoldCurveProblem::initial_guess() { return state(inner_.initial_guess(), inner_.parameters().value(p1_)); }

double FoldCurveProblem::difference_step(const Vector& u) const {
  const double vn = v_.lpNorm<Eigen::Infinity>();
  return 1e-5 * std::max(1.0, u.lpNorm<Eigen::Infinity>()) / std::max(vn, 1e-300);
}

Status FoldCurveProblem::analyse(const Vector& U) {
  ParameterSet& ps = inner_.parameters();
  if (U.size() != n_ + 1) throw std::invalid_argument("fold curve: state of the wrong size");
  if (!std::isfinite(U[n_])) return {StatusCode::NotFinite, "fold curve: " + fold_parameter_name() + " is not finite"};
  if (!ps.admissible(p1_, U[n_]))
    return {StatusCode::InvalidState,
            fmt::format("fold curve: {} = {} is outside its range", fold_parameter_name(), U[n_])};
  ps.set(p1_, U[n_]);
  if (analysed_.size() == U.size() && analysed_ == U && analysed_params_ == parameter_values(ps))
    return analysed_status_;
  analysed_ = U;
  analysed_params_ = parameter_values(ps);
  analysed_status_ = [&]() -> Status {
    const Vector u = U.head(n_);
    Status st = inner_.jacobian(u, F_, J_);
    if (!st.is_ok()) return st;
    const SparseMatrix M = bordered(J_, b_, c_, 0.0);
    st = lu_.factorize(M);
    if (!st.is_ok()) return st;
    Vector rhs = Vector::Zero(n_ + 1), x;
    rhs[n_] = 1.0;
    st = lu_.solve(rhs, x);
    if (!st.is_ok()) return st;
    v_ = x.head(n_);
    g_ = x[n_];
    st = lu_.solve(rhs, x, true);
    if (!st.is_ok()) return st;
    w_ = x.head(n_);
    if (!std::isfinite(g_) || !v_.allFinite() || !w_.allFinite())
      return {StatusCode::NotFinite, "fold curve: the bordered solve for the test function is not finite"};
    return {};
  }();
  return analysed_status_;
}

Status FoldCurveProblem::residual(const Vector& U, Vector& F) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  F.resize(n_ + 1);
  F.head(n_) = F_;
  F[n_] = g_;
  return {};
}

Status FoldCurveProblem::parameter_term(int p, const Vector& u, double& gp) {
  const double h = difference_step(u);
  Vector Fp_plus, Fp_minus;
  Status st = inner_.parameter_derivative(p, u + h * v_, Fp_plus);
  if (st.is_ok()) st = inner_.parameter_derivative(p, u - h * v_, Fp_minus);
  if (!st.is_ok()) return st;
  gp = -w_.dot(Fp_plus - Fp_minus) / (2.0 * h);
  return {};
}

Status FoldCurveProblem::jacobian(const Vector& U, Vector& F, SparseMatrix& J) {
  Status st = residual(U, F);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  const Vector v = v_, w = w_;
  const SparseMatrix J0 = J_;
  const double h = difference_step(u);
  Vector scratch;
  SparseMatrix Jp, Jm;
  st = inner_.jacobian(u + h * v, scratch, Jp);
  if (st.is_ok()) st = inner_.jacobian(u - h * v, scratch, Jm);
  if (!st.is_ok()) return st;
  // g_u = -(w^T J_u v)^T = -(dJ/dv)^T w (F_uu symmetric in its two arguments)
  const SparseMatrix D = (Jp - Jm) / (2.0 * h);
  const Vector gu = -(D.transpose() * w);
  Vector Fp1;
  st = inner_.parameter_derivative(p1_, u, Fp1);
  if (!st.is_ok()) return st;
  double gp1 = 0.0;
  st = parameter_term(p1_, u, gp1);
  if (!st.is_ok()) return st;
  J = bordered(J0, Fp1, gu, gp1);
  return {};
}

Status FoldCurveProblem::parameter_derivative(int p, const Vector& U, Vector& dF) {
  if (p == p1_)
    throw std::invalid_argument("fold curve: " + fold_parameter_name() +
                                " is an unknown of the curve, not the parameter it is continued in");
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  Vector Fp;
  st = inner_.parameter_derivative(p, u, Fp);
  if (!st.is_ok()) return st;
  double gp = 0.0;
  st = parameter_term(p, u, gp);
  if (!st.is_ok()) return st;
  dF.resize(n_ + 1);
  dF.head(n_) = Fp;
  dF[n_] = gp;
  return {};
}

Status FoldCurveProblem::null_vectors(const Vector& U, Vector& v, Vector& w, double& g) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  v = v_;
  w = w_;
  g = g_;
  return {};
}

Status FoldCurveProblem::quadratic_coefficient(const Vector& U, double& a) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  const Vector v = v_, w = w_;
  const double h = difference_step(u);
  Vector scratch;
  SparseMatrix Jp, Jm;
  st = inner_.jacobian(u + h * v, scratch, Jp);
  if (st.is_ok()) st = inner_.jacobian(u - h * v, scratch, Jm);
  if (!st.is_ok()) return st;
  a = w.dot(Jp * v - Jm * v) / (2.0 * h);
  return {};
}

Status FoldCurveProblem::update_borders(const Vector& U) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  const double vn = v_.norm(), wn = w_.norm();
  if (!(vn > 0.0) || !(wn > 0.0)) return {StatusCode::SingularMatrix, "fold curve: a null vector vanished"};
  c_ = v_ / vn;
  b_ = w_ / wn;
  analysed_.resize(0);  // the borders changed: g and the null vectors with them
  return {};
}

Status FoldCurveProblem::set_borders(const Vector& U, const Vector& null_guess) {
  if (null_guess.size() != n_) throw std::invalid_argument("fold curve: null vector guess of the wrong size");
  const double nn = null_guess.norm();
  if (!(nn > 0.0)) throw std::invalid_argument("fold curve: the null vector guess vanishes");
  c_ = null_guess / nn;
  b_ = c_;
  analysed_.resize(0);
  for (int k = 0; k < 3; ++k) {
    Status st = update_borders(U);
    if (!st.is_ok()) return st;
  }
  return {};
}

Status FoldCurveProblem::start(Vector& U, const Vector& null_guess, const NewtonOptions& newton, SparseLUOptions lu) {
  Status st = set_borders(U, null_guess);
  if (!st.is_ok()) return st;
  NewtonSolver solver(*this, newton, lu);
  const NewtonResult r = solver.solve(U);
  if (!r.converged())
    return {StatusCode::NotConverged,
            "fold curve: Newton from the located fold did not converge (" + r.status.describe() + ")"};
  return update_borders(U);
}

std::vector<std::string> FoldCurveProblem::observable_names() const {
  std::vector<std::string> names = inner_.observable_names();
  names.push_back(fold_parameter_name());
  return names;
}

Status FoldCurveProblem::observables(const Vector& U, std::vector<double>& values) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  st = inner_.observables(U.head(n_), values);
  if (!st.is_ok()) return st;
  values.push_back(U[n_]);
  return {};
}

std::vector<std::string> FoldCurveProblem::monitor_names() const {
  std::vector<std::string> names = inner_.monitor_names();
  names.push_back("cusp");
  return names;
}

Status FoldCurveProblem::monitors(const Vector& U, std::vector<double>& values) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  st = inner_.monitors(U.head(n_), values);
  if (!st.is_ok()) return st;
  double a = 0.0;
  st = quadratic_coefficient(U, a);
  if (!st.is_ok()) return st;
  values.push_back(a);
  return {};
}

std::string FoldCurveProblem::summary() const {
  return fmt::format("fold curve (minimally augmented, unknowns the state and {}) of {}", fold_parameter_name(),
                     inner_.summary());
}

void FoldCurveProblem::BorderUpdate::on_point(const BranchPoint& p) {
  // a failure here leaves the borders where they were: still regular near this point
  (void)curve_.update_borders(p.u);
  next_.on_point(p);
}

}  // namespace keller
