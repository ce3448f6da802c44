#include "problems/analytic/Pitchfork1DProblem.hpp"

#include "problems/analytic/Grid1D.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace keller {

Pitchfork1DProblem::Pitchfork1DProblem(int intervals, double lambda, double eps) : n_(intervals) {
  if (intervals < 2) throw std::invalid_argument("pitchfork1d: need at least 2 intervals");
  params_.add("lambda", lambda, "coefficient of the linear term (branch points of u = 0 near (k pi)^2)");
  params_.add("eps", eps, "imperfection: constant source that breaks the symmetry u -> -u");
  pattern_ = grid1d::tridiagonal_pattern(size());
}

Status Pitchfork1DProblem::residual(const Vector& u, Vector& F) {
  const int m = size();
  const double lambda = params_.value(0), eps = params_.value(1), ih2 = 1.0 / (h() * h());
  F.resize(m);
  for (int i = 0; i < m; ++i) {
    const double l = i > 0 ? u[i - 1] : 0.0, r = i + 1 < m ? u[i + 1] : 0.0;
    F[i] = -(l - 2.0 * u[i] + r) * ih2 - lambda * u[i] + u[i] * u[i] * u[i] - eps;
  }
  if (!F.allFinite()) return {StatusCode::NotFinite, "pitchfork1d residual overflow"};
  return {};
}

Status Pitchfork1DProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  Status st = residual(u, F);
  if (!st.is_ok()) return st;
  const double lambda = params_.value(0), ih2 = 1.0 / (h() * h());
  grid1d::fill_tridiagonal(pattern_, (2.0 * ih2 - lambda + 3.0 * u.array().square()).matrix(), -ih2, J);
  return {};
}

Status Pitchfork1DProblem::parameter_derivative(int p, const Vector& u, Vector& dF) {
  if (p == 0)
    dF = -u;
  else
    dF = Vector::Constant(size(), -1.0);
  return {};
}

Status Pitchfork1DProblem::mass_matrix(const Vector&, SparseMatrix& B) {
  grid1d::fill_tridiagonal(pattern_, Vector::Ones(size()), 0.0, B);
  return {};
}

double Pitchfork1DProblem::value_at(const Vector& u, double x) const {
  // grid value i is u(i h), with u = 0 at i = 0 and i = n; linear in between
  auto node = [&](int i) { return (i <= 0 || i >= n_) ? 0.0 : u[i - 1]; };
  const double s = x * n_;
  const int i = std::clamp(static_cast<int>(std::floor(s)), 0, n_ - 1);
  const double f = s - i;
  return (1.0 - f) * node(i) + f * node(i + 1);
}

Status Pitchfork1DProblem::observables(const Vector& u, std::vector<double>& values) {
  values = {value_at(u, 0.5), value_at(u, 0.25), std::sqrt(h() * u.squaredNorm()), u.maxCoeff()};
  return {};
}

SolutionFields Pitchfork1DProblem::fields(const Vector& u) const {
  SolutionFields f;
  f.arrays.push_back(grid1d::profile(u, n_));
  return f;
}

std::string Pitchfork1DProblem::summary() const {
  return fmt::format(
      "1D pitchfork u'' + lambda u - u^3 + eps = 0, central differences on {} intervals, {} unknowns; "
      "branch points of u = 0 at lambda_1 = {:.10g}, lambda_2 = {:.10g}",
      n_, size(), branch_point(1, n_), branch_point(2, n_));
}

double Pitchfork1DProblem::branch_point(int k, int intervals) {
  const double h = 1.0 / intervals, s = std::sin(k * std::numbers::pi * h / 2.0);
  return 4.0 / (h * h) * s * s;
}

void Pitchfork1DProblem::declare(SceneSchema& s) {
  s.section("pitchfork", "pitchfork problem u'' + lambda u - u^3 + eps = 0 with u = 0 on the boundary");
  s.integer("pitchfork.intervals", 64, "grid intervals on (0, 1)", Range::between(2, max_grid_intervals));
  s.section("parameters", "initial values of the named continuation parameters");
  s.real("parameters.lambda", 1.0, "coefficient of the linear term (branch points of u = 0 near (k pi)^2)");
  s.real("parameters.eps", 0.0, "imperfection: constant source that breaks the symmetry u -> -u (0: perfect)");
}

std::unique_ptr<Problem> Pitchfork1DProblem::from_scene(const Scene& scene) {
  return std::make_unique<Pitchfork1DProblem>(static_cast<int>(scene.integer("pitchfork.intervals")),
                                              scene.real("parameters.lambda"), scene.real("parameters.eps"));
}

}  // namespace keller
