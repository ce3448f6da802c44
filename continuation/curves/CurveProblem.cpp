#include "continuation/curves/CurveProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

namespace {
// The relative step of a central difference in a parameter (the truncation error h^2 and the
// rounding error eps / h balance near 1e-5; derivatives of smooth residuals in their parameters
// are checked to 1e-6 relative with this step).
constexpr double kParameterStep = 1e-6;
// The relative step of the central differences along a direction of the state.
constexpr double kDirectionStep = 1e-5;

double direction_step(const Vector& u, const Vector& d) {
  const double dn = d.lpNorm<Eigen::Infinity>();
  return dn > 0 ? kDirectionStep * std::max(1.0, u.lpNorm<Eigen::Infinity>()) / dn : 1.0;
}

std::vector<double> parameter_values(const ParameterSet& ps) { return {ps.values(), ps.values() + ps.size()}; }
}  // namespace

CurveProblem::CurveProblem(Problem& inner, const std::string& p1, int tail, std::string what)
    : inner_(inner), n_(inner.size()), tail_(tail), p1_(inner.parameters().index(p1)), what_(std::move(what)) {
  if (inner_.parameters().size() < 2)
    throw std::invalid_argument(what_ + " of '" + inner_.name() + "': the problem has only one parameter");
  if (tail < 1) throw std::invalid_argument(what_ + ": a curve has at least p1 as an unknown");
  pattern_ = blocks().assembled();
}

const SparseMatrix& CurveProblem::inner_pattern() const {
  return border_size() > 0 ? inner_.jacobian_pattern() : pattern_;
}

Status CurveProblem::jacobian(const Vector& U, Vector& F, SparseMatrix& J) {
  BorderedJacobian A = blocks();
  const Status st = bordered_jacobian(U, F, A);
  if (st.is_ok()) J = A.assembled();
  return st;
}

BorderedJacobian CurveProblem::blocks() const {
  BorderedJacobian J;
  J.K = inner_.jacobian_pattern();
  J.B = Matrix::Zero(n_, tail_);
  J.C = Matrix::Zero(n_, tail_);
  J.D = Matrix::Zero(tail_, tail_);
  return J;
}

Vector CurveProblem::state(const Vector& u, double p1, const Vector& extra) const {
  if (u.size() != n_ || extra.size() > tail_ - 1) throw std::invalid_argument(what_ + ": a state of the wrong size");
  Vector U = Vector::Zero(size());
  U.head(n_) = u;
  U[n_] = p1;
  if (extra.size()) U.segment(n_ + 1, extra.size()) = extra;
  return U;
}

Status CurveProblem::set_p1(const Vector& U) const {
  if (U.size() != size()) throw std::invalid_argument(what_ + ": state of the wrong size");
  const double v = U[n_];
  if (!std::isfinite(v)) return {StatusCode::NotFinite, what_ + ": " + p1_name() + " is not finite"};
  if (!inner_.parameters().admissible(p1_, v))
    return {StatusCode::InvalidState, fmt::format("{}: {} = {} is outside its range", what_, p1_name(), v)};
  inner_.parameters().set(p1_, v);
  return {};
}

Status CurveProblem::parameter_derivative(int p, const Vector& U, Vector& dF) {
  if (p == p1_)
    throw std::invalid_argument(what_ + ": " + p1_name() +
                                " is an unknown of the curve, not the parameter it is continued in");
  Vector d, Fp;
  Status st = equations_parameter_derivative(p, U, d);
  if (st.is_ok()) st = inner_.parameter_derivative(p, U.head(n_), Fp);
  if (!st.is_ok()) return st;
  dF.resize(size());
  dF.head(n_) = Fp;
  dF.tail(tail_) = d;
  return {};
}

FixedParameterResult CurveProblem::solve_here(Vector& U, const NewtonOptions& newton, const SparseLUOptions& lu,
                                              const StartFactorisation& near) {
  // every parameter is fixed; the bordered system's extra column is that of any but p1
  const int p = p1_ == 0 ? 1 : 0;
  return solve_at_fixed_parameter(*this, inner_.parameters().info(p).name, U, newton, lu, near);
}

bool CurveProblem::analysed_at(const Vector& U) {
  const std::vector<double> values = parameter_values(inner_.parameters());
  if (analysed_.size() == U.size() && analysed_ == U && analysed_params_ == values) return true;
  analysed_ = U;
  analysed_params_ = values;
  return false;
}

Status CurveProblem::parameter_difference(int p, const std::function<Status(Vector&)>& value,
                                          Vector& derivative) const {
  ParameterSet& ps = inner_.parameters();
  const double v = ps.value(p), h = kParameterStep * std::max(1.0, std::abs(v));
  const auto [lo, hi] = ps.difference_points(p, h);
  if (hi == lo)
    return {StatusCode::InvalidState,
            fmt::format("d/d{}: no room for a difference inside its admissible range", ps.info(p).name)};
  Vector fhi, flo;
  ps.set(p, hi);
  Status st = value(fhi);
  ps.set(p, lo);
  if (st.is_ok()) st = value(flo);
  ps.set(p, v);
  if (!st.is_ok()) return st;
  derivative = (fhi - flo) / (hi - lo);
  return {};
}

Status CurveProblem::jacobian_along(const Vector& u, const Vector& d, SparseMatrix& D) const {
  const double h = direction_step(u, d);
  Vector scratch;
  SparseMatrix Jp, Jm;
  Status st = inner_.jacobian(u + h * d, scratch, Jp);
  if (st.is_ok()) st = inner_.jacobian(u - h * d, scratch, Jm);
  if (!st.is_ok()) return st;
  D = (Jp - Jm) / (2.0 * h);
  return {};
}

Status CurveProblem::parameter_derivative_along(int p, const Vector& u, const Vector& d, Vector& D) const {
  const double h = direction_step(u, d);
  Vector Fp, Fm;
  Status st = inner_.parameter_derivative(p, u + h * d, Fp);
  if (st.is_ok()) st = inner_.parameter_derivative(p, u - h * d, Fm);
  if (!st.is_ok()) return st;
  D = (Fp - Fm) / (2.0 * h);
  return {};
}

std::vector<std::string> CurveProblem::curve_observable_names(const std::vector<std::string>& extra) const {
  std::vector<std::string> names = inner_.observable_names();
  names.push_back(p1_name());
  names.insert(names.end(), extra.begin(), extra.end());
  return names;
}

}  // namespace keller
