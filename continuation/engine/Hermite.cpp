#include "continuation/engine/Hermite.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace keller {

namespace {

// Cubic Hermite basis on [0, 1] and its derivative.
struct HermiteBasis {
  double h00, h10, h01, h11;
};
HermiteBasis basis(double x) {
  const double x2 = x * x, x3 = x2 * x;
  return {2 * x3 - 3 * x2 + 1, x3 - 2 * x2 + x, -2 * x3 + 3 * x2, x3 - x2};
}
HermiteBasis basis_derivative(double x) {
  const double x2 = x * x;
  return {6 * x2 - 6 * x, 3 * x2 - 4 * x + 1, -6 * x2 + 6 * x, 3 * x2 - 2 * x};
}

// Newton's iteration for the fraction where the cubic takes the target: at most this many steps,
// until a step is below kFractionStep (rounding of a fraction in [0, 1]); the cubic must then
// take the target to kCubicMatch of the values' scale, or it has no such point on the segment.
constexpr int kCubicNewtonSteps = 30;
constexpr double kFractionStep = 1e-15;
constexpr double kCubicMatch = 1e-12;

// Both points have tangents of the states' size, and b lies beyond a along the branch.
bool has_tangents(const BranchPoint& a, const BranchPoint& b) {
  return b.s > a.s && std::isfinite(b.s - a.s) && a.tu.size() == a.u.size() && b.tu.size() == b.u.size() &&
         a.u.size() == b.u.size();
}

// The point at x (0 at a, 1 at b, beyond 1 past b) on the cubic through a and b.
void cubic_at(const BranchPoint& a, const BranchPoint& b, double x, Vector& u, double& lambda) {
  const double h = b.s - a.s;
  const HermiteBasis w = basis(x);
  u = w.h00 * a.u + (w.h10 * h) * a.tu + w.h01 * b.u + (w.h11 * h) * b.tu;
  lambda = w.h00 * a.lambda + (w.h10 * h) * a.tlambda + w.h01 * b.lambda + (w.h11 * h) * b.tlambda;
}

// Where g along the cubic through a and b equals target, by Newton from x0 (none: from the chord
// between the ends' values): the x where the cubic
// takes it to kCubicMatch of the values' scale, or nullopt. (Newton stops where its step is at
// rounding; near the root, rounding of g - target can make it wander instead, so the answer is
// judged by the cubic's value there.) g is affine, so along the cubic it is the cubic with g's
// values and slopes at the ends.
std::optional<double> cubic_root(const BranchPoint& a, const BranchPoint& b, const BranchFunctional& g, double target,
                                 std::optional<double> x0) {
  const double h = b.s - a.s;
  const double ga = g(a.u, a.lambda, true), gb = g(b.u, b.lambda, true);
  const double sa = h * g(a.tu, a.tlambda, false), sb = h * g(b.tu, b.tlambda, false);
  const auto g_at = [&](const HermiteBasis& w) { return w.h00 * ga + w.h10 * sa + w.h01 * gb + w.h11 * sb; };
  double x = x0 ? *x0 : (target - ga) / (gb - ga);
  if (!std::isfinite(x)) return std::nullopt;
  for (int it = 0; it < kCubicNewtonSteps; ++it) {
    const double d = g_at(basis_derivative(x));
    if (!(std::abs(d) > 0)) break;
    const double dx = (g_at(basis(x)) - target) / d;
    if (!std::isfinite(dx)) return std::nullopt;
    x -= dx;
    if (std::abs(dx) <= kFractionStep * std::max(1.0, std::abs(x))) break;
  }
  const double scale = std::max({std::abs(ga), std::abs(gb), std::abs(target), std::numeric_limits<double>::min()});
  if (!std::isfinite(x) || std::abs(g_at(basis(x)) - target) > kCubicMatch * scale) return std::nullopt;
  return x;
}

}  // namespace

bool hermite_point(const BranchPoint& a, const BranchPoint& b, const BranchFunctional& g, double target, Vector& u,
                   double& lambda, double& x) {
  if (!has_tangents(a, b)) return false;
  const std::optional<double> t = cubic_root(a, b, g, target, std::nullopt);
  if (!t || !(*t >= 0.0 && *t <= 1.0)) return false;
  cubic_at(a, b, *t, u, lambda);
  x = *t;
  return true;
}

bool hermite_extrapolate(const BranchPoint& a, const BranchPoint& b, double sigma, Vector& u, double& lambda) {
  if (!has_tangents(a, b) || !std::isfinite(sigma)) return false;
  cubic_at(a, b, 1.0 + sigma / (b.s - a.s), u, lambda);
  return true;
}

std::optional<double> hermite_extrapolate_to(const BranchPoint& a, const BranchPoint& b, const BranchFunctional& g,
                                             double target, double sigma0) {
  if (!has_tangents(a, b) || !std::isfinite(sigma0)) return std::nullopt;
  const double h = b.s - a.s;
  const std::optional<double> x = cubic_root(a, b, g, target, 1.0 + sigma0 / h);
  if (!x) return std::nullopt;
  return (*x - 1.0) * h;
}

}  // namespace keller
