// Closed forms of steady simple shear that the tests compare keller's laws with, written apart
// from the laws (problems/laws) so that a slip in one is not copied into the other.
#pragma once

#include <cmath>

#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller::test {

// The real root of f^2 (f - 1) = c (c >= 0) by Cardano: with f = y + 1/3, y^3 + p y + q = 0,
// p = -1/3, q = -(2/27 + c), whose discriminant (q/2)^2 + (p/3)^3 = c/27 + c^2/4 is positive:
// y = A + B, A = cbrt(h + s), B = cbrt(h - s), h = -q/2, s = sqrt(discriminant). Since
// A B = -p/3 = 1/9, B = 1/(9 A), which avoids the cancellation in h - s at large c.
inline double peterlin_cardano(double c) {
  const double h = 1.0 / 27.0 + 0.5 * c, s = std::sqrt(c / 27.0 + 0.25 * c * c);
  const double A = std::cbrt(h + s);
  return 1.0 / 3.0 + A + 1.0 / (9.0 * A);
}

// FENE-P's polymer viscosity over its zero-shear value at W = lambda gdot: 1 / f with
// f^2 (f - 1) = 2 W^2 / (3 b).
inline double fene_p_viscosity_ratio(double W, double b) { return 1.0 / peterlin_cardano(2 * W * W / (3 * b)); }

// The Cross law of Fang and Owens in Pa s at the dimensional shear rate r (1/s):
// eta_s + eta_p0 (1 + theta1 r^m) / (1 + theta2 r^m), theta1 = theta2 eta_pinf / eta_p0.
inline double cross_viscosity(const OwensParameters& o, double r) {
  const double x = std::pow(r, o.m);
  return o.eta_s + o.eta_p0 * (1 + o.theta2 * o.eta_pinf / o.eta_p0 * x) / (1 + o.theta2 * x);
}

}  // namespace keller::test
