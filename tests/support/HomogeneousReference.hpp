// Independent reference states of steady homogeneous flows for the law tests: each law's equation
// written out on its own in long double, in stress form where the literature states it so,
//   Oldroyd-B  t - (L t + t L^T) = 2 D                     (t = tau_p / G, lambda = 1, L = W Lhat)
//   Giesekus   t + alpha t.t - (L t + t L^T) = 2 D
//   PTT        Y(tr t) t - (L t + t L^T) + xi (D t + t D) = 2 D,  Y = 1 + eps tr t or exp(eps tr t)
//   FENE-P     (f c - I) - (L c + c L^T) = 0,  t = f c - I,    f = (b - 1) / (b - tr c / 3)
//   FENE-CR    f (c - I) - (L c + c L^T) = 0,  t = f (c - I)
// over the 3x3 tensor with components (xx, xy, yy, zz), solved by Newton with a difference
// Jacobian and continued from rest in W, so that nothing here shares code or algebra with the
// laws under test (problems/laws), whose k0 I + k1 M + k2 M^2 form and closed forms it checks.
#pragma once

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <stdexcept>

#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller::test {

using Tensor = std::array<long double, 4>;  // xx, xy, yy, zz

struct ReferenceLaw {
  FluidModel model = FluidModel::OldroydB;
  long double b = 100, alpha = 0, epsilon = 0, xi = 0;
};

// The flow's velocity gradient per unit W: shear [[0,1],[0,0]], planar diag(1,-1,0), uniaxial diag(1,-1/2,-1/2).
struct Gradient {
  long double xx = 0, xy = 0, yx = 0, yy = 0, zz = 0;
};
inline Gradient shear_gradient() { return {0, 1, 0, 0, 0}; }
inline Gradient planar_gradient() { return {1, 0, 0, -1, 0}; }
inline Gradient uniaxial_gradient() { return {1, 0, 0, -0.5L, -0.5L}; }

// L t + t L^T for symmetric t with t_xz = t_yz = 0.
inline Tensor stretch(const Gradient& L, const Tensor& t) {
  return {2 * (L.xx * t[0] + L.xy * t[1]), L.xx * t[1] + L.xy * t[2] + t[0] * L.yx + t[1] * L.yy,
          2 * (L.yx * t[1] + L.yy * t[2]), 2 * L.zz * t[3]};
}

// The residual of the law at unknown x (t, or c for the FENE laws) for gradient W L.
inline Tensor reference_residual(const ReferenceLaw& law, const Gradient& Lhat, long double W, const Tensor& x) {
  const Gradient L{W * Lhat.xx, W * Lhat.xy, W * Lhat.yx, W * Lhat.yy, W * Lhat.zz};
  const Tensor D{L.xx, 0.5L * (L.xy + L.yx), L.yy, L.zz};
  const Tensor s = stretch(L, x);
  Tensor r{};
  switch (law.model) {
    case FluidModel::FeneP:
    case FluidModel::FeneCr: {
      const long double f = (law.b - 1) / (law.b - (x[0] + x[2] + x[3]) / 3);
      const Tensor I{1, 0, 1, 1};
      for (int i = 0; i < 4; ++i) r[i] = (law.model == FluidModel::FeneP ? f * x[i] - I[i] : f * (x[i] - I[i])) - s[i];
      return r;
    }
    case FluidModel::Giesekus: {
      const Tensor tt{x[0] * x[0] + x[1] * x[1], x[1] * (x[0] + x[2]), x[1] * x[1] + x[2] * x[2], x[3] * x[3]};
      for (int i = 0; i < 4; ++i) r[i] = x[i] + law.alpha * tt[i] - s[i] - 2 * D[i];
      return r;
    }
    case FluidModel::PttLinear:
    case FluidModel::PttExponential: {
      const long double tr = x[0] + x[2] + x[3];
      const long double Y = law.model == FluidModel::PttLinear ? 1 + law.epsilon * tr : std::exp(law.epsilon * tr);
      const Tensor dt{2 * D[0] * x[0] + 2 * D[1] * x[1], D[0] * x[1] + D[1] * x[2] + x[0] * D[1] + x[1] * D[2],
                      2 * D[1] * x[1] + 2 * D[2] * x[2], 2 * D[3] * x[3]};
      for (int i = 0; i < 4; ++i) r[i] = Y * x[i] - s[i] + law.xi * dt[i] - 2 * D[i];
      return r;
    }
    default:
      for (int i = 0; i < 4; ++i) r[i] = x[i] - s[i] - 2 * D[i];
      return r;
  }
}

// The polymer stress over the modulus, t, of a reference solution x.
inline Tensor reference_stress(const ReferenceLaw& law, const Tensor& x) {
  if (law.model != FluidModel::FeneP && law.model != FluidModel::FeneCr) return x;
  const long double f = (law.b - 1) / (law.b - (x[0] + x[2] + x[3]) / 3);
  if (law.model == FluidModel::FeneP) return {f * x[0] - 1, f * x[1], f * x[2] - 1, f * x[3] - 1};
  return {f * (x[0] - 1), f * x[1], f * (x[2] - 1), f * (x[3] - 1)};
}

// Newton from x at W; true when an update is below 1e-17 of the solution's size: Newton
// converges quadratically, so the state is then exact to long double rounding amplified by the
// law's conditioning (which a residual threshold cannot see: near full extension a FENE law's
// residual is 1e4 times as sensitive to M as M is to the data).
inline bool reference_newton(const ReferenceLaw& law, const Gradient& Lhat, long double W, Tensor& x) {
  for (int it = 0; it < 60; ++it) {
    const Tensor r = reference_residual(law, Lhat, W, x);
    Eigen::Matrix<long double, 4, 4> J;
    for (int j = 0; j < 4; ++j) {
      Tensor xp = x, xm = x;
      const long double h = 1e-7L * std::max<long double>(1, std::abs(x[j]));
      xp[j] += h;
      xm[j] -= h;
      const Tensor rp = reference_residual(law, Lhat, W, xp), rm = reference_residual(law, Lhat, W, xm);
      for (int i = 0; i < 4; ++i) J(i, j) = (rp[i] - rm[i]) / (2 * h);
    }
    Eigen::Matrix<long double, 4, 1> R;
    for (int i = 0; i < 4; ++i) R[i] = r[i];
    const Eigen::Matrix<long double, 4, 1> dx = J.fullPivLu().solve(-R);
    long double size = 1, step = 0;
    for (int i = 0; i < 4; ++i) {
      x[i] += dx[i];
      size = std::max(size, std::abs(x[i]));
      step = std::max(step, std::abs(dx[i]));
    }
    if (!std::isfinite(static_cast<double>(step))) return false;
    if (step <= 1e-17L * size) return true;
  }
  return false;
}

// The reference stress t at W, continued from rest (t = 0, c = I) in steps that halve where
// Newton does not converge. Throws std::runtime_error if the continuation stalls.
inline Tensor reference_state(const ReferenceLaw& law, const Gradient& Lhat, long double W) {
  const bool fene = law.model == FluidModel::FeneP || law.model == FluidModel::FeneCr;
  Tensor x = fene ? Tensor{1, 0, 1, 1} : Tensor{0, 0, 0, 0};
  long double at = 0, step = std::min<long double>(W, 0.05L);
  while (at < W) {
    const long double next = std::min(W, at + step);
    Tensor y = x;
    // a root with c = I + t (or the FENE laws' c) not positive definite, or a FENE root with
    // tr c >= 3b (f < 0), is not the physical state: a shorter step
    const bool converged = reference_newton(law, Lhat, next, y);
    const Tensor c = fene ? y : Tensor{1 + y[0], y[1], 1 + y[2], 1 + y[3]};
    const bool physical =
        c[0] > 0 && c[3] > 0 && c[0] * c[2] > c[1] * c[1] && (!fene || c[0] + c[2] + c[3] < 3 * law.b);
    if (converged && physical) {
      x = y;
      at = next;
      step *= 1.5L;
    } else {
      step *= 0.5L;
      if (step < 1e-12L * (1 + W)) throw std::runtime_error("reference continuation stalled");
    }
  }
  return reference_stress(law, x);
}

}  // namespace keller::test
