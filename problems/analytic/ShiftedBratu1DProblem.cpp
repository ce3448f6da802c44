#include "problems/analytic/ShiftedBratu1DProblem.hpp"

#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Grid1D.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

ShiftedBratu1DProblem::ShiftedBratu1DProblem(int intervals, double lambda, double mu) : n_(intervals) {
  if (intervals < 2) throw std::invalid_argument("bratu1d-shifted: need at least 2 intervals");
  params_.add("lambda", lambda, "Bratu parameter");
  params_.add("mu", mu, "coefficient of the linear term mu u");
  pattern_ = grid1d::tridiagonal_pattern(size());
}

Status ShiftedBratu1DProblem::residual(const Vector& u, Vector& F) {
  const int m = size();
  const double lambda = params_.value(0), mu = params_.value(1), ih2 = 1.0 / (h() * h());
  F.resize(m);
  for (int i = 0; i < m; ++i) {
    const double l = i > 0 ? u[i - 1] : 0.0, r = i + 1 < m ? u[i + 1] : 0.0;
    F[i] = -(l - 2.0 * u[i] + r) * ih2 - mu * u[i] - lambda * std::exp(u[i]);
  }
  if (!F.allFinite()) return {StatusCode::NotFinite, "bratu1d-shifted residual overflow"};
  return {};
}

Status ShiftedBratu1DProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  Status st = residual(u, F);
  if (!st.is_ok()) return st;
  const double lambda = params_.value(0), mu = params_.value(1), ih2 = 1.0 / (h() * h());
  grid1d::fill_tridiagonal(pattern_, (2.0 * ih2 - mu - lambda * u.array().exp()).matrix(), -ih2, J);
  return {};
}

Status ShiftedBratu1DProblem::parameter_derivative(int p, const Vector& u, Vector& dF) {
  if (p == 0)
    dF = -u.array().exp().matrix();
  else
    dF = -u;
  return {};
}

Status ShiftedBratu1DProblem::mass_matrix(const Vector&, SparseMatrix& B) {
  grid1d::fill_tridiagonal(pattern_, Vector::Ones(size()), 0.0, B);
  return {};
}

Status ShiftedBratu1DProblem::observables(const Vector& u, std::vector<double>& values) {
  const double mid = (n_ % 2 == 0) ? u[n_ / 2 - 1] : 0.5 * (u[n_ / 2 - 1] + u[n_ / 2]);
  values = {mid, u.maxCoeff()};
  return {};
}

SolutionFields ShiftedBratu1DProblem::fields(const Vector& u) const {
  SolutionFields f;
  f.arrays.push_back(grid1d::profile(u, n_));
  return f;
}

std::string ShiftedBratu1DProblem::summary() const {
  return fmt::format("1D Bratu with a linear term mu u, central differences on {} intervals, {} unknowns", n_, size());
}

void ShiftedBratu1DProblem::declare(SceneSchema& s) {
  Bratu1DProblem::declare(s);
  s.real("bratu.mu", 0.0, "initial value of the coefficient mu of the linear term (bratu1d-shifted)");
}

std::unique_ptr<Problem> ShiftedBratu1DProblem::from_scene(const Scene& scene) {
  return std::make_unique<ShiftedBratu1DProblem>(static_cast<int>(scene.integer("bratu.intervals")),
                                                 scene.real("bratu.lambda"), scene.real("bratu.mu"));
}

}  // namespace keller
