#include "continuation/engine/ArclengthNorm.hpp"

#include <cmath>
#include <stdexcept>

namespace keller {

double Constraint::value(const Vector& u, double lambda) const {
  double N = cl * (lambda - l0) - target;
  if (cu.size()) N += u0 ? cu.dot(u - *u0) : cu.dot(u);
  return N;
}

Constraint Constraint::parameter(double value) {
  Constraint c;
  c.cl = 1.0;
  c.target = value;
  return c;
}

ArclengthNorm::ArclengthNorm(int n, double state_scale, double theta)
    : scale_(state_scale), wu_(theta / (static_cast<double>(n) * state_scale * state_scale)), wl_(1.0 - theta) {
  if (!(state_scale > 0) || !(theta > 0 && theta < 1) || n <= 0)
    throw std::invalid_argument("ArclengthNorm: need n > 0, state scale > 0 and theta in (0, 1)");
}

double ArclengthNorm::norm(const Vector& u, double l) const { return std::sqrt(dot(u, l, u, l)); }

double ArclengthNorm::distance(const BranchPoint& a, const BranchPoint& b) const {
  return norm(b.u - a.u, b.lambda - a.lambda);
}

Constraint ArclengthNorm::arclength(const BranchPoint& from, const Vector& tu, double tl, double sigma) const {
  Constraint c;
  c.cu = wu_ * tu;
  c.cl = wl_ * tl;
  c.u0 = &from.u;
  c.l0 = from.lambda;
  c.target = sigma;
  return c;
}

Constraint ArclengthNorm::tangent_row(const Vector& tu, double tl) const {
  Constraint c;
  c.cu = wu_ * tu;
  c.cl = wl_ * tl;
  return c;
}

}  // namespace keller
