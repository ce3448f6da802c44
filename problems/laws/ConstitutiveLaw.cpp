#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

const char* to_string(FluidModel m) {
  switch (m) {
    case FluidModel::Newtonian: return "newtonian";
    case FluidModel::OldroydB: return "oldroyd-b";
    case FluidModel::FeneP: return "fene-p";
    case FluidModel::Owens: return "owens";
  }
  return "?";
}

FluidModel fluid_model_from_string(const std::string& s) {
  for (auto m : {FluidModel::Newtonian, FluidModel::OldroydB, FluidModel::FeneP, FluidModel::Owens})
    if (s == to_string(m)) return m;
  throw std::invalid_argument("unknown fluid model '" + s + "' (newtonian, oldroyd-b, fene-p, owens)");
}

namespace {

// Root of f^2 (f - 1) = c, c >= 0, the one with f >= 1 (Newton from above: the cubic is convex
// there, so the iteration decreases monotonically to the root).
double peterlin_shear_root(double c) {
  double f = 1.0 + std::cbrt(c) + c;  // an upper bound: f^2 (f - 1) >= f - 1 for f >= 1
  for (int it = 0; it < 200; ++it) {
    const double g = f * f * (f - 1.0) - c, dg = 3.0 * f * f - 2.0 * f;
    const double step = g / dg;
    f -= step;
    if (std::abs(step) <= 1e-16 * f) break;
  }
  return f;
}

}  // namespace

SteadyConformation steady_shear(FluidModel model, double W, double b) {
  SteadyConformation s;
  if (model != FluidModel::FeneP) {
    s.xx = 1.0 + 2.0 * W * W;
    s.xy = W;
    return s;
  }
  const double f = peterlin_shear_root(2.0 * W * W / (3.0 * b));
  s.f = f;
  s.yy = s.zz = 1.0 / f;
  s.xy = W / (f * f);
  s.xx = (1.0 + 2.0 * W * W / (f * f)) / f;
  return s;
}

SteadyConformation planar_elongation(FluidModel model, double W, double b) {
  SteadyConformation s;
  if (model != FluidModel::FeneP) {
    if (!(2.0 * W < 1.0)) throw std::domain_error("planar elongation: no steady Oldroyd-B state for lambda eps >= 1/2");
    s.xx = 1.0 / (1.0 - 2.0 * W);
    s.yy = 1.0 / (1.0 + 2.0 * W);
    return s;
  }
  // f = (b - 1) / (b - tr M / 3) with tr M = 1/(f - 2W) + 1/(f + 2W) + 1/f: bisection on
  // h(f) = f (b - tr M(f) / 3) - (b - 1), increasing for f > 2|W|.
  auto h = [&](double f) { return f * (b - (1.0 / (f - 2 * W) + 1.0 / (f + 2 * W) + 1.0 / f) / 3.0) - (b - 1.0); };
  double lo = 2.0 * std::abs(W) * (1.0 + 1e-15) + 1e-300, hi = std::max(1.0, 4.0 * std::abs(W) + 1.0);
  while (h(hi) < 0) hi *= 2.0;
  for (int it = 0; it < 400; ++it) {
    const double mid = 0.5 * (lo + hi);
    (h(mid) < 0 ? lo : hi) = mid;
  }
  const double f = 0.5 * (lo + hi);
  s.f = f;
  s.xx = 1.0 / (f - 2.0 * W);
  s.yy = 1.0 / (f + 2.0 * W);
  s.zz = 1.0 / f;
  return s;
}

double shear_viscosity(FluidModel model, double gdot, double Wi, double Gamma, double beta, double b,
                       const OwensParameters& owens) {
  switch (model) {
    case FluidModel::Newtonian: return 1.0;
    case FluidModel::OldroydB: return 1.0;
    case FluidModel::FeneP: return beta + (1.0 - beta) / steady_shear(model, Wi / Gamma * gdot, b).f;
    case FluidModel::Owens: return beta + (1.0 - beta) * owens_factor(gdot * gdot, Gamma, owens);  // 2 D:D = gdot^2
  }
  return 1.0;
}

}  // namespace keller
