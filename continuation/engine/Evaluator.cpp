#include "continuation/engine/Evaluator.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/ConvergenceTest.hpp"

namespace keller {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
}  // namespace

Evaluator::Evaluator(Problem& problem, int parameter, std::string parameter_name)
    : problem_(problem),
      p_(parameter),
      name_(std::move(parameter_name)),
      augmented_(augmented(problem)),
      gradients_(monitor_gradients(problem)),
      pieces_(pieces_of(problem)),
      bordered_(augmented_ && augmented_->border_size() > 0),
      J_(problem.jacobian_pattern()) {}

Status Evaluator::set_parameter(double lambda) {
  ParameterSet& ps = problem_.parameters();
  if (!std::isfinite(lambda)) return {StatusCode::NotFinite, "parameter is not finite"};
  if (!ps.admissible(p_, lambda))
    return {StatusCode::InvalidState, fmt::format("{} = {} is outside its admissible range [{}, {}]", name_, lambda,
                                                  ps.info(p_).lower, ps.info(p_).upper)};
  ps.set(p_, lambda);
  return {};
}

Status Evaluator::residual(const Vector& u, Vector& F) {
  const auto t0 = Clock::now();
  const Status st = problem_.residual(u, F);
  timings_.residual += since(t0);
  ++timings_.residuals;
  return st;
}

Status Evaluator::jacobian(const Vector& u) {
  const auto t0 = Clock::now();
  const Status st = bordered_ ? augmented_->bordered_jacobian(u, F_, JB_) : problem_.jacobian(u, F_, J_);
  timings_.jacobian += since(t0);
  ++timings_.jacobians;
  assembled_ = !bordered_;
  if (st.is_ok()) floor_ = bordered_ ? JB_.rounding_floor(u) : keller::rounding_floor(J_, u);
  return st;
}

Status Evaluator::border(const Vector& u, BorderedJacobian& J) {
  if (!augmented_) throw std::logic_error("problem '" + problem_.name() + "' has no border");
  const auto t0 = Clock::now();
  const Status st = augmented_->border(u, F_, J);
  timings_.jacobian += since(t0);
  if (st.is_ok()) floor_ = J.rounding_floor(u);  // (of K as it is: made nearby)
  return st;
}

GradientFunction Evaluator::gradient_function(int index, bool observable, double threshold) {
  if (!gradients_ ||
      !(observable ? gradients_->has_observable_gradient(index) : gradients_->has_monitor_gradient(index)))
    return nullptr;
  const auto value = [this, index, observable](const Vector& u, double& out) {
    std::vector<double> v;
    const Status st = observable ? problem_.observables(u, v) : problem_.monitors(u, v);
    if (st.is_ok()) out = v[static_cast<size_t>(index)];
    return st;
  };
  const auto gradient = [this, index, observable](const Vector& u, Vector& gu) {
    return observable ? gradients_->observable_gradient(index, u, gu) : gradients_->monitor_gradient(index, u, gu);
  };
  return timed_function(value, gradient, threshold);
}

Status Evaluator::smallest_piece(int observable, const Vector& u, double lambda, int& piece) {
  if (!has_pieces(observable))
    throw std::logic_error("observable " + std::to_string(observable) + " of '" + problem_.name() + "' has no pieces");
  const Status st = set_parameter(lambda);
  return st.is_ok() ? pieces_->smallest_piece(observable, u, piece) : st;
}

GradientFunction Evaluator::piece_function(int observable, int piece, double threshold) {
  if (!has_pieces(observable))
    throw std::logic_error("observable " + std::to_string(observable) + " of '" + problem_.name() + "' has no pieces");
  const auto value = [this, observable, piece](const Vector& u, double& out) {
    return pieces_->piece_value(observable, piece, u, out);
  };
  const auto gradient = [this, observable, piece](const Vector& u, Vector& gu) {
    return pieces_->piece_gradient(observable, piece, u, gu);
  };
  return timed_function(value, gradient, threshold);
}

GradientFunction Evaluator::timed_function(StateValue value, StateGradient gradient_in_u, double threshold) {
  return [this, value = std::move(value), gradient_in_u = std::move(gradient_in_u), threshold](
             const Vector& u, double lambda, double h, bool gradient, double& g, Vector& gu, double& gl) {
    const auto t0 = Clock::now();
    const auto at = [&](double l, double& out) {
      Status st = set_parameter(l);
      if (st.is_ok()) st = value(u, out);
      if (st.is_ok()) out -= threshold;
      return st;
    };
    Status st = at(lambda, g);
    double plus = 0.0, minus = 0.0;
    if (st.is_ok() && gradient) {
      st = at(lambda + h, plus);
      if (st.is_ok()) st = at(lambda - h, minus);
      if (st.is_ok()) st = set_parameter(lambda);
      if (st.is_ok()) {
        gl = (plus - minus) / (2.0 * h);
        st = gradient_in_u(u, gu);
      }
    }
    timings_.observables += since(t0);
    return st;
  };
}

const SparseMatrix& Evaluator::jacobian_matrix() const {
  if (!assembled_) {
    J_ = JB_.assembled();
    assembled_ = true;
  }
  return J_;
}

Status Evaluator::parameter_derivative(const Vector& u) {
  const auto t0 = Clock::now();
  const Status st = problem_.parameter_derivative(p_, u, Fp_);
  timings_.parameter_derivative += since(t0);
  ++timings_.parameter_derivatives;
  return st;
}

Status Evaluator::jacobian_times(const Vector& u, const Vector& v, Vector& out) {
  const double vmax = v.lpNorm<Eigen::Infinity>();
  if (!(vmax > 0)) {
    out = Vector::Zero(u.size());
    return {};
  }
  // the step that balances truncation (h^2) and rounding (eps / h) of a central difference
  const double ustep = std::cbrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, u.lpNorm<Eigen::Infinity>());
  const double eps = ustep / vmax;
  Status st = residual(u + eps * v, plus_);
  if (st.is_ok()) st = residual(u - eps * v, minus_);
  if (!st.is_ok()) return st;
  out = (plus_ - minus_) / (2.0 * eps);
  return {};
}

}  // namespace keller
