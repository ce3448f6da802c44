#include "continuation/time/TimeStepControl.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace keller {

Vector SdirkTableau::embedded_error(double h, const std::array<const Vector*, kStages>& K) const {
  Vector e = Vector::Zero(K[0]->size());
  for (size_t j = 0; j < kStages; ++j) e += (h * (b[j] - b_hat[j])) * *K[j];
  return e;
}

const SdirkTableau& sdirk4() {
  static const SdirkTableau t = [] {
    SdirkTableau s;
    s.gamma = 0.25;
    s.a = {{{0.25, 0.0, 0.0, 0.0, 0.0},
            {0.5, 0.25, 0.0, 0.0, 0.0},
            {17.0 / 50.0, -1.0 / 25.0, 0.25, 0.0, 0.0},
            {371.0 / 1360.0, -137.0 / 2720.0, 15.0 / 544.0, 0.25, 0.0},
            {25.0 / 24.0, -49.0 / 48.0, 125.0 / 16.0, -85.0 / 12.0, 0.25}}};
    s.b = s.a[4];
    s.b_hat = {59.0 / 48.0, -17.0 / 96.0, 225.0 / 32.0, -85.0 / 12.0, 0.0};
    s.c = {0.25, 0.75, 11.0 / 20.0, 0.5, 1.0};
    return s;
  }();
  return t;
}

std::array<double, 3> bdf_coefficients(int order, double h, double h_prev) {
  if (order == 1) return {1.0, -1.0, 0.0};
  if (order != 2) throw std::invalid_argument("bdf_coefficients: order 1 or 2");
  const double w = h / h_prev;
  return {(1.0 + 2.0 * w) / (1.0 + w), -(1.0 + w), w * w / (1.0 + w)};
}

std::array<double, 3> extrapolation_weights(int points, double h, double h1, double h2) {
  if (points <= 1) return {1.0, 0.0, 0.0};
  if (points == 2) return {1.0 + h / h1, -h / h1, 0.0};
  // Lagrange weights at t = t_n + h of the nodes t_n = 0, t_(n-1) = -h1, t_(n-2) = -(h1 + h2)
  const double a = 0.0, b = -h1, c = -(h1 + h2), t = h;
  return {(t - b) * (t - c) / ((a - b) * (a - c)), (t - a) * (t - c) / ((b - a) * (b - c)),
          (t - a) * (t - b) / ((c - a) * (c - b))};
}

double bdf2_error_factor(double h, double h1, double h2) {
  const double w = h / h1;
  const double r = h * (1.0 + w) / (1.0 + 2.0 * w);
  return r / (h + h1 + h2 + r);
}

StepDecision decide_step(double error, double h, int order, double min_step, double max_step) {
  StepDecision d;
  d.accept = error <= 1.0;
  double factor = kMaxStepGrowth;
  if (std::isnan(error))
    factor = kMinStepFactor;  // no estimate: cut as far as allowed
  else if (error > 0.0)
    factor = kStepSafety * std::pow(error, -1.0 / (order + 1));
  factor = std::clamp(factor, kMinStepFactor, kMaxStepGrowth);
  if (!d.accept) factor = std::min(factor, 1.0);
  d.next = std::clamp(h * factor, min_step, max_step);
  return d;
}

bool keeps_factorisation(double now, double factorised) {
  return factorised > 0.0 && std::abs(now / factorised - 1.0) <= kMaxMatrixCoefficientChange;
}

}  // namespace keller
