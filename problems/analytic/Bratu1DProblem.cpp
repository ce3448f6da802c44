#include "problems/analytic/Bratu1DProblem.hpp"

#include "problems/analytic/Grid1D.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

Bratu1DProblem::Bratu1DProblem(int intervals, double lambda) : n_(intervals) {
  if (intervals < 2) throw std::invalid_argument("bratu1d: need at least 2 intervals");
  params_.add("lambda", lambda, "Bratu parameter");
  pattern_ = grid1d::tridiagonal_pattern(size());
}

Status Bratu1DProblem::residual(const Vector& u, Vector& F) {
  const int m = size();
  const double lambda = params_.value(0), ih2 = 1.0 / (h() * h());
  F.resize(m);
  for (int i = 0; i < m; ++i) {
    const double l = i > 0 ? u[i - 1] : 0.0, r = i + 1 < m ? u[i + 1] : 0.0;
    F[i] = -(l - 2.0 * u[i] + r) * ih2 - lambda * std::exp(u[i]);
  }
  if (!F.allFinite()) return {StatusCode::NotFinite, "bratu1d residual overflow"};
  return {};
}

Status Bratu1DProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  Status st = residual(u, F);
  if (!st.is_ok()) return st;
  const double lambda = params_.value(0), ih2 = 1.0 / (h() * h());
  grid1d::fill_tridiagonal(pattern_, (2.0 * ih2 - lambda * u.array().exp()).matrix(), -ih2, J);
  return {};
}

Status Bratu1DProblem::parameter_derivative(int, const Vector& u, Vector& dF) {
  dF = -u.array().exp().matrix();
  return {};
}

Status Bratu1DProblem::mass_matrix(const Vector&, SparseMatrix& B) {
  grid1d::fill_tridiagonal(pattern_, Vector::Ones(size()), 0.0, B);
  return {};
}

Status Bratu1DProblem::observables(const Vector& u, std::vector<double>& values) {
  // u(1/2): the middle node for even n, linear interpolation otherwise
  const double mid = (n_ % 2 == 0) ? u[n_ / 2 - 1] : 0.5 * (u[n_ / 2 - 1] + u[n_ / 2]);
  values = {mid, u.maxCoeff()};
  return {};
}

SolutionFields Bratu1DProblem::fields(const Vector& u) const {
  SolutionFields f;
  f.arrays.push_back(grid1d::profile(u, n_));
  return f;
}

std::string Bratu1DProblem::summary() const {
  return fmt::format("1D Bratu, central differences on {} intervals, {} unknowns", n_, size());
}

double Bratu1DProblem::exact(double x, double lambda, bool upper) {
  // theta solves g(theta) = theta - c cosh(theta / 4) = 0, c = sqrt(2 lambda). g(0) < 0, g rises
  // to its maximum at theta* = 4 asinh(4 / c) and falls for ever after: the lower branch is the
  // root below theta*, the upper branch the root above; none if g(theta*) < 0 (lambda > lambda_c).
  const double c = std::sqrt(2.0 * lambda);
  auto g = [c](double th) { return th - c * std::cosh(th / 4.0); };
  const double thstar = 4.0 * std::asinh(4.0 / c);
  if (g(thstar) < 0.0) throw std::invalid_argument("bratu1d: no solution for lambda > lambda_c");
  double lo = 0.0, hi = thstar;
  if (upper) {
    lo = thstar;
    hi = 2.0 * thstar;
    while (g(hi) > 0.0) hi *= 2.0;
  }
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    // the sign of g at the lower end of the bracket is - (lower branch) or + (upper branch)
    ((g(mid) > 0.0) != upper ? hi : lo) = mid;
  }
  const double th = 0.5 * (lo + hi);
  return -2.0 * std::log(std::cosh((x - 0.5) * th / 2.0) / std::cosh(th / 4.0));
}

void Bratu1DProblem::declare(SceneSchema& s) {
  s.section("bratu", "Bratu problem u'' + lambda e^u = 0 with u = 0 on the boundary");
  s.integer("bratu.intervals", 64, "grid intervals (1D) or elements per side (2D, at most 4000)",
            Range::between(2, max_grid_intervals));
  s.real("bratu.lambda", 1.0, "initial value of the parameter lambda", Range::non_negative());
}

std::unique_ptr<Problem> Bratu1DProblem::from_scene(const Scene& scene) {
  return std::make_unique<Bratu1DProblem>(static_cast<int>(scene.integer("bratu.intervals")),
                                          scene.real("bratu.lambda"));
}

}  // namespace keller
