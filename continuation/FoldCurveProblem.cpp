#include "continuation/FoldCurveProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

namespace {

std::vector<double> parameter_values(const ParameterSet& ps) { return {ps.values(), ps.values() + ps.size()}; }

// Bordered solves that refine borders set from a guess of the null vector (inverse iteration:
// each multiplies the error by the ratio of the two eigenvalues nearest zero).
constexpr int kBorderRefinements = 3;

}  // namespace

FoldCurveProblem::FoldCurveProblem(Problem& inner, const std::string& fold_parameter, SparseLUOptions lu)
    : inner_(inner), unknowns_(inner, fold_parameter, 1, "fold curve"), n_(inner.size()), test_(inner.size(), lu) {}

Vector FoldCurveProblem::initial_guess() {
  return state(inner_.initial_guess(), inner_.parameters().value(unknowns_.p1()));
}

Status FoldCurveProblem::analyse(const Vector& U) {
  Status st = unknowns_.set_p1(U);
  if (!st.is_ok()) return st;
  const ParameterSet& ps = inner_.parameters();
  if (analysed_.size() == U.size() && analysed_ == U && analysed_params_ == parameter_values(ps))
    return analysed_status_;
  analysed_ = U;
  analysed_params_ = parameter_values(ps);
  analysed_status_ = inner_.jacobian(U.head(n_), F_, J_);
  if (analysed_status_.is_ok()) analysed_status_ = test_.evaluate(J_);
  return analysed_status_;
}

Status FoldCurveProblem::residual(const Vector& U, Vector& F) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  F.resize(n_ + 1);
  F.head(n_) = F_;
  F[n_] = test_.g();
  return {};
}

Status FoldCurveProblem::parameter_term(int p, const Vector& u, double& gp) {
  Vector D;
  const Status st = unknowns_.parameter_derivative_along(p, u, test_.v(), D);
  if (st.is_ok()) gp = -test_.w().dot(D);
  return st;
}

Status FoldCurveProblem::jacobian(const Vector& U, Vector& F, SparseMatrix& J) {
  Status st = residual(U, F);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  const Vector v = test_.v(), w = test_.w();
  const SparseMatrix J0 = J_;
  SparseMatrix D;
  st = unknowns_.jacobian_along(u, v, D);
  if (!st.is_ok()) return st;
  // g_u = -(w^T J_u v)^T = -(dJ/dv)^T w (F_uu symmetric in its two arguments)
  const Vector gu = -(D.transpose() * w);
  Vector Fp1;
  st = inner_.parameter_derivative(unknowns_.p1(), u, Fp1);
  if (!st.is_ok()) return st;
  double gp1 = 0.0;
  st = parameter_term(unknowns_.p1(), u, gp1);
  if (!st.is_ok()) return st;
  BorderedJacobian A;
  A.K = J0;
  A.B = Fp1;
  A.C = gu;
  A.D = Matrix::Constant(1, 1, gp1);
  J = A.assembled();
  return {};
}

Status FoldCurveProblem::parameter_derivative(int p, const Vector& U, Vector& dF) {
  if (p == unknowns_.p1())
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
  v = test_.v();
  w = test_.w();
  g = test_.g();
  return {};
}

Status FoldCurveProblem::quadratic_coefficient(const Vector& U, double& a) {
  Status st = analyse(U);
  if (!st.is_ok()) return st;
  const Vector v = test_.v(), w = test_.w();
  SparseMatrix D;
  st = unknowns_.jacobian_along(U.head(n_), v, D);
  if (st.is_ok()) a = w.dot(D * v);
  return st;
}

Status FoldCurveProblem::update_borders(const Vector& U) {
  Status st = analyse(U);
  if (st.is_ok()) st = test_.update_borders();
  if (!st.is_ok()) return {st.code(), "fold curve: " + st.message()};
  analysed_.resize(0);  // the borders changed: g and the null vectors with them
  return {};
}

Status FoldCurveProblem::set_borders(const Vector& U, const Vector& null_guess) {
  test_.set_borders(null_guess);
  analysed_.resize(0);
  for (int k = 0; k < kBorderRefinements; ++k) {
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

std::vector<std::string> FoldCurveProblem::observable_names() const { return unknowns_.observable_names(); }

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

}  // namespace keller
