#include "problems/laws/SteadyFlows.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace keller {

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

// The root of an increasing h on (lo, hi) with h(lo+) < 0 <= h(hi) by bisection to rounding
// (a cold path: inflow states and reference values). R: double, or long double where the state
// amplifies the root's rounding (the FENE laws near full extension: M_xx = 1 / (f - 2W)).
template <class R>
R increasing_root(const std::function<R(R)>& h, R lo, R hi) {
  for (int it = 0; it < 20000 && hi - lo > 0; ++it) {
    const R mid = (lo + hi) / 2;
    if (mid <= lo || mid >= hi) break;
    (h(mid) < 0 ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

// An upper end of the bracket: doubles from `start` until h >= 0.
template <class R>
R bracket_above(const std::function<R(R)>& h, R start) {
  R hi = start;
  for (int it = 0; it < 2000 && h(hi) < 0; ++it) hi *= 2;
  return hi;
}

double ptt_function(FluidModel model, double epsilon, double trace_excess) {
  return model == FluidModel::PttLinear ? 1.0 + epsilon * trace_excess : std::exp(epsilon * trace_excess);
}

SteadyConformation giesekus_shear(double W, double alpha) {
  // Bird, Armstrong and Hassager: with x = 16 alpha (1 - alpha) W^2, chi^2 = (sqrt(1 + x) - 1) / (x / 2)
  // and f = (1 - chi) / (1 + (1 - 2 alpha) chi): eta_p / eta_p0 = (1 - f)^2 / (1 + (1 - 2 alpha) f),
  // tau_yy = -f, tau_xx - tau_yy = 2 f (1 - alpha f) / (alpha (1 - f)). Written without the
  // cancellations at small alpha W^2: chi^2 = 2 / (sqrt(1 + x) + 1), 1 - chi = (1 - chi^2) / (1 + chi),
  // 1 - chi^2 = x / (sqrt(1 + x) + 1)^2, so f = alpha W^2 r with
  // r = 16 (1 - alpha) / ((sqrt(1 + x) + 1)^2 (1 + chi) (1 + (1 - 2 alpha) chi)) (r = 1 at alpha = 0).
  const double a = std::abs(W), x = 16.0 * alpha * (1.0 - alpha) * a * a, sq = std::sqrt(1.0 + x);
  const double chi = std::sqrt(2.0 / (sq + 1.0));
  const double r = 16.0 * (1.0 - alpha) / ((sq + 1.0) * (sq + 1.0) * (1.0 + chi) * (1.0 + (1.0 - 2.0 * alpha) * chi));
  const double f = alpha * a * a * r;
  SteadyConformation s;
  s.xy = W * (1.0 - f) * (1.0 - f) / (1.0 + (1.0 - 2.0 * alpha) * f);
  s.yy = 1.0 - f;
  s.xx = s.yy + 2.0 * a * a * r * (1.0 - alpha * f) / (1.0 - f);
  return s;
}

SteadyConformation ptt_shear(FluidModel model, double W, const LawConstants<double>& c) {
  // q = tau_xx + tau_yy = 2 W^2 (1 - xi) / (Y(q)^2 + W^2 xi (2 - xi)): g(q) = q - that is
  // increasing, g(0) <= 0 and g(q_max) >= 0 at q_max, the value for Y = 1. Newton inside the
  // bracket (bisection where a step leaves it): a few steps, as the inflow profiles call this
  // at every quadrature point
  const double xi = c.xi, k = W * W * xi * (2.0 - xi), top = 2.0 * W * W * (1.0 - xi);
  double lo = 0.0, hi = top / (1.0 + k), q = hi;
  for (int it = 0; it < 200 && top > 0; ++it) {
    const double Y = ptt_function(model, c.epsilon, q), dY = model == FluidModel::PttLinear ? c.epsilon : c.epsilon * Y;
    const double d = Y * Y + k, g = q - top / d, dg = 1.0 + top * 2.0 * Y * dY / (d * d);
    (g < 0 ? lo : hi) = q;
    double next = q - g / dg;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const bool done = std::abs(next - q) <= 1e-16 * q || hi - lo <= 1e-16 * hi;
    q = next;
    if (done) break;
  }
  if (!(top > 0)) q = 0.0;
  const double Y = ptt_function(model, c.epsilon, q);
  const double t = W * Y / (Y * Y + k);
  SteadyConformation s;
  s.f = Y;
  s.xy = t;
  s.xx = 1.0 + W * (2.0 - xi) * t / Y;
  s.yy = 1.0 - W * xi * t / Y;
  return s;
}

}  // namespace

SteadyConformation steady_shear(FluidModel model, double W, const LawConstants<double>& c) {
  SteadyConformation s;
  switch (model) {
    case FluidModel::FeneP: {
      const double f = peterlin_shear_root(2.0 * W * W / (3.0 * c.b));
      s.f = f;
      s.yy = s.zz = 1.0 / f;
      s.xy = W / (f * f);
      s.xx = (1.0 + 2.0 * W * W / (f * f)) / f;
      return s;
    }
    case FluidModel::FeneCr: {
      // f (b - 1 - 2 W^2 / (3 f^2)) = b - 1 with M_yy = M_zz = 1, M_xx = 1 + 2 W^2 / f^2
      const double f = 0.5 * (1.0 + std::sqrt(1.0 + 8.0 * W * W / (3.0 * (c.b - 1.0))));
      s.f = f;
      s.xy = W / f;
      s.xx = 1.0 + 2.0 * W * W / (f * f);
      return s;
    }
    case FluidModel::Giesekus: return giesekus_shear(W, c.alpha);
    case FluidModel::PttLinear:
    case FluidModel::PttExponential: return ptt_shear(model, W, c);
    default:
      s.xx = 1.0 + 2.0 * W * W;
      s.xy = W;
      return s;
  }
}

const char* to_string(Extension e) { return e == Extension::Planar ? "planar" : "uniaxial"; }

SteadyConformation steady_extension(FluidModel model, Extension kind, double W, const LawConstants<double>& c) {
  if (!(W >= 0)) throw std::domain_error("steady extension: needs lambda eps >= 0");
  const double w[3] = {W, kind == Extension::Planar ? -W : -0.5 * W, kind == Extension::Planar ? 0.0 : -0.5 * W};
  double m[3] = {1, 1, 1};  // M_i
  SteadyConformation s;
  switch (model) {
    case FluidModel::FeneP:
    case FluidModel::FeneCr: {
      // f (b - tr M / 3) = b - 1 with M_i = 1 / (f - 2 w_i) (FENE-P) or f / (f - 2 w_i) (FENE-CR),
      // in long double: near full extension f - 2W is 1/M_xx, and its rounding is M_xx's
      using LD = long double;
      const bool p = model == FluidModel::FeneP;
      const LD b = c.b;
      auto trace = [&](LD f) {
        LD t = 0;
        for (double wi : w) t += (p ? LD(1) : f) / (f - 2 * LD(wi));
        return t;
      };
      const std::function<LD(LD)> h = [&](LD f) { return f * (b - trace(f) / 3) - (b - 1); };
      const LD lo = 2 * LD(W) * (1 + 1e-18L) + 1e-300L;
      const LD f = increasing_root<LD>(h, lo, bracket_above<LD>(h, std::max<LD>(1, 4 * LD(W) + 1)));
      s.f = static_cast<double>(f);
      for (int i = 0; i < 3; ++i) m[i] = static_cast<double>((p ? LD(1) : f) / (f - 2 * LD(w[i])));
      break;
    }
    case FluidModel::Giesekus:
      for (int i = 0; i < 3; ++i) {
        // the root of alpha t^2 + a t - 2 w = 0 (a = 1 - 2 w) that is 0 at w = 0, in the form
        // without cancellation: 4 w / (a + d) for a >= 0, (d - a) / (2 alpha) for a < 0
        const double a = 1.0 - 2.0 * w[i], d = std::sqrt(a * a + 8.0 * c.alpha * w[i]);
        if (a >= 0)
          m[i] = 1.0 + 4.0 * w[i] / (a + d);
        else if (c.alpha > 0)
          m[i] = 1.0 + (d - a) / (2.0 * c.alpha);
        else
          throw std::domain_error("steady extension: no steady Oldroyd-B state for lambda eps >= 1/2");
      }
      break;
    case FluidModel::PttLinear:
    case FluidModel::PttExponential: {
      const double a = 1.0 - c.xi, top = 2.0 * a * W;  // the largest 2 (1 - xi) w_i
      if (!(c.epsilon > 0) && !(top < 1.0))
        throw std::domain_error(
            "steady extension: no steady PTT state with epsilon = 0 for 2 (1 - xi) lambda eps >= 1");
      using LD = long double;
      auto q = [&](LD Y) {
        LD t = 0;
        for (double wi : w) t += 2 * LD(wi) / (Y - 2 * LD(a) * LD(wi));
        return t;
      };
      const std::function<LD(LD)> h = [&](LD Y) {
        const LD x = LD(c.epsilon) * q(Y);
        return Y - (model == FluidModel::PttLinear ? 1 + x : std::exp(x));
      };
      const LD lo = std::max<LD>(1, 2 * LD(a) * LD(W) * (1 + 1e-18L));  // the pole of M_xx, in LD
      const LD Y = h(lo) >= 0 ? lo : increasing_root<LD>(h, lo, bracket_above<LD>(h, 2 * lo + 1));
      s.f = static_cast<double>(Y);
      for (int i = 0; i < 3; ++i) m[i] = static_cast<double>(1 + 2 * LD(w[i]) / (Y - 2 * LD(a) * LD(w[i])));
      break;
    }
    default:
      if (!(2.0 * W < 1.0))
        throw std::domain_error("steady extension: no steady Oldroyd-B state for lambda eps >= 1/2");
      for (int i = 0; i < 3; ++i) m[i] = 1.0 / (1.0 - 2.0 * w[i]);
  }
  s.xx = m[0];
  s.yy = m[1];
  s.zz = m[2];
  return s;
}

double polymer_shear_ratio(FluidModel model, double W, const LawConstants<double>& c) {
  if (W == 0.0) return 1.0;
  const SteadyConformation s = steady_shear(model, W, c);
  const double stress = uses_b(model) ? s.f * s.xy : s.xy;  // tau_xy / modulus = s1 M_xy
  return stress / W;
}

double shear_viscosity(FluidModel model, double gdot, double Wi, double Gamma, double beta,
                       const LawConstants<double>& c, const OwensParameters& owens) {
  switch (model) {
    case FluidModel::Newtonian: return 1.0;
    case FluidModel::Owens: return beta + (1.0 - beta) * owens_factor(gdot * gdot, Gamma, owens);  // 2 D:D = gdot^2
    default: return beta + (1.0 - beta) * polymer_shear_ratio(model, Wi / Gamma * gdot, c);
  }
}

}  // namespace keller
