#include "continuation/curves/FoldCurveProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

namespace {

// Bordered solves that refine borders set from a guess of the null vector (inverse iteration:
// each multiplies the error by the ratio of the two eigenvalues nearest zero).
constexpr int kBorderRefinements = 3;

}  // namespace

FoldCurveProblem::FoldCurveProblem(Problem& inner, const std::string& fold_parameter, SparseLUOptions lu)
    : CurveProblem(inner, fold_parameter, 1, "fold curve"), test_(inner.size(), lu) {}

Status FoldCurveProblem::analyse(const Vector& U) {
  Status st = set_p1(U);
  if (!st.is_ok()) return st;
  if (analysed_at(U)) return analysed_status_;
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
  const Status st = parameter_derivative_along(p, u, test_.v(), D);
  if (st.is_ok()) gp = -test_.w().dot(D);
  return st;
}

Status FoldCurveProblem::bordered_jacobian(const Vector& U, Vector& F, BorderedJacobian& J) {
  Status st = residual(U, F);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  const Vector v = test_.v(), w = test_.w();
  const SparseMatrix J0 = J_;
  SparseMatrix D;
  st = jacobian_along(u, v, D);
  if (!st.is_ok()) return st;
  // g_u = -(w^T J_u v)^T = -(dJ/dv)^T w (F_uu symmetric in its two arguments)
  const Vector gu = -(D.transpose() * w);
  Vector Fp1;
  st = inner_.parameter_derivative(p1(), u, Fp1);
  if (!st.is_ok()) return st;
  double gp1 = 0.0;
  st = parameter_term(p1(), u, gp1);
  if (!st.is_ok()) return st;
  J.K = J0;
  J.B = Fp1;
  J.C = gu;
  J.D = Matrix::Constant(1, 1, gp1);
  return {};
}

Status FoldCurveProblem::equations_parameter_derivative(int p, const Vector& U, Vector& d) {
  double gp = 0.0;
  Status st = analyse(U);
  if (st.is_ok()) st = parameter_term(p, U.head(n_), gp);
  d = Vector::Constant(1, gp);
  return st;
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
  st = jacobian_along(U.head(n_), v, D);
  if (st.is_ok()) a = w.dot(D * v);
  return st;
}

Status FoldCurveProblem::update_borders(const Vector& U) {
  Status st = analyse(U);
  if (st.is_ok()) st = test_.update_borders();
  if (!st.is_ok()) return {st.code(), "fold curve: " + st.message()};
  forget_analysis();  // the borders changed: g and the null vectors with them
  return {};
}

Status FoldCurveProblem::set_borders(const Vector& U, const Vector& null_guess) {
  test_.set_borders(null_guess);
  forget_analysis();
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
  return fmt::format("fold curve (minimally augmented, unknowns the state and {}) of {}", p1_name(), inner_.summary());
}

}  // namespace keller
