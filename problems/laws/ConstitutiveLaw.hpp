// Constitutive laws of model.md and the ones rheologists reach for next, pointwise and templated
// on the scalar type; laws never see meshes. Every law here is a conformation-tensor law
//   M^box = -(1/lambda_eff) P(M),   tau_p = modulus (s0 I + s1 M),   modulus = (1 - beta) Gamma / Wi,
// with M^box the upper-convected derivative (PTT with xi > 0: the Gordon-Schowalter derivative,
// below), P(M) = k0 I + k1 M + k2 M^2 a function of M alone (so it commutes with M, which the
// log-conformation form needs) and lambda_eff = lambda = Wi / Gamma except for Owens:
//
//   law              k0               k1          k2      s0, s1     factor (must stay > 0)
//   Oldroyd-B        -1               1           0       -1, 1      1
//   FENE-P           -1               f           0       -1, f      f = (b - 1) / (b - tr M / 3)
//   Owens            -1               1           0       -1, 1      1 (lambda_eff = lambda eta_p(gdot)/eta_p0)
//   Giesekus         alpha - 1        1 - 2 alpha alpha   -1, 1      1: P = (M - I) + alpha (M - I)^2
//   PTT (linear)     -Y               Y           0       -1, 1      Y = 1 + epsilon (tr M - 3)
//   PTT (exp.)       -Y               Y           0       -1, 1      Y = exp(epsilon (tr M - 3))
//   FENE-CR          -f               f           0       -f, f      f = (b - 1) / (b - tr M / 3)
//
// tr M is over the 3x3 tensor. In planar flow M_xz = M_yz = 0, and for every law but FENE-P
// M_zz = 1 is a steady state of its own equation (P_zz(M_zz = 1) = 0), so M_zz = 1 needs no
// unknown; FENE-P's f M_zz = 1 eliminates it (model.md). The Gordon-Schowalter derivative of the
// PTT model, tau^box = tau^nabla + xi (D tau + tau D), is in conformation terms the upper-convected
// derivative with L replaced by L - xi D plus a source: M^box = M^nabla + xi (D M + M D) - 2 xi D.
//
// Units (model.md): stresses in G, velocities in G W / eta0, so eta0 = 1, the solvent
// viscosity is beta, lambda = Wi / Gamma and the polymer modulus is (1 - beta) Gamma / Wi.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

namespace keller {

enum class FluidModel { Newtonian, OldroydB, FeneP, Owens, Giesekus, PttLinear, PttExponential, FeneCr };
const char* to_string(FluidModel m);
FluidModel fluid_model_from_string(const std::string& s);  // throws std::invalid_argument

// Which constants a law takes (each may be a continuation parameter).
inline bool uses_b(FluidModel m) { return m == FluidModel::FeneP || m == FluidModel::FeneCr; }
inline bool uses_alpha(FluidModel m) { return m == FluidModel::Giesekus; }
inline bool is_ptt(FluidModel m) { return m == FluidModel::PttLinear || m == FluidModel::PttExponential; }

// The constants of a law, of scalar type P (double, or a dual number for parameter derivatives).
// Only those the law uses are read.
template <class P>
struct LawConstants {
  P b = P(100.0);      // FENE-P, FENE-CR: extensibility, tr M < 3b (b > 1)
  P alpha = P(0.0);    // Giesekus mobility, 0 <= alpha <= 1/2
  P epsilon = P(0.0);  // PTT, epsilon >= 0
  P xi = P(0.0);       // PTT slip of the Gordon-Schowalter derivative, 0 <= xi < 1
};

// Where a law's constants sit in a problem's parameter set (-1: not a parameter of this law).
struct LawParameterIndices {
  int b = -1, alpha = -1, epsilon = -1, xi = -1;
};

// The law's constants at the current parameters (those the law does not use keep their defaults).
template <class P>
LawConstants<P> law_constants(const LawParameterIndices& p, const P* params) {
  LawConstants<P> c;
  if (p.b >= 0) c.b = params[p.b];
  if (p.alpha >= 0) c.alpha = params[p.alpha];
  if (p.epsilon >= 0) c.epsilon = params[p.epsilon];
  if (p.xi >= 0) c.xi = params[p.xi];
  return c;
}

// Cross model of blood (Fang and Owens): eta_p(gdot) = eta_p0 (1 + theta1 gdot^m) / (1 + theta2 gdot^m)
// with the dimensional shear rate gdot_dim = gdot * rate_scale / Gamma (rate_scale = U0 / W).
struct OwensParameters {
  double eta_p0 = 0.197;    // Pa s
  double eta_pinf = 0.003;  // Pa s
  double eta_s = 0.001;     // Pa s
  double theta2 = 8.0;      // s^m
  double m = 0.75;
  double rate_scale = 100.0;  // U0 / W in 1/s (U0 = 0.01 m/s, W = 100 micrometres)
  // The Cross model's gdot^m has an infinite slope at gdot = 0 (centrelines, stagnation
  // points): gdot_dim is replaced by sqrt(gdot_dim^2 + floor^2), which lowers eta_p by 0.025%
  // at gdot_dim = 0 (theta2 floor^m = 2.5e-4), less elsewhere, and keeps the Jacobian finite.
  double rate_floor = 1e-6;  // 1/s
  double theta1() const { return theta2 * eta_pinf / eta_p0; }
  double beta() const { return eta_s / (eta_s + eta_p0); }
};

// Peterlin factor of FENE-P, f = (b - 1) / (b - tr M / 3) over the full 3x3 tensor. With the
// out-of-plane component eliminated by f M_zz = 1 (steady flow): f = (b - 2/3) / (b - (M_xx + M_yy)/3).
template <class T, class P>
T peterlin_eliminated(const T& mxx, const T& myy, const P& b) {
  return (b - 2.0 / 3.0) / (b - (mxx + myy) / 3.0);
}
template <class T, class P>
T peterlin_full(const T& mxx, const T& myy, const T& mzz, const P& b) {
  return (b - 1.0) / (b - (mxx + myy + mzz) / 3.0);
}

// Owens: eta_p(gdot) / eta_p0, with gdot2 = 2 D:D of the (interpolated) velocity gradient in
// model units and Gamma the velocity scale.
template <class T, class P>
T owens_factor(const T& gdot2, const P& Gamma, const OwensParameters& o) {
  using std::pow;
  using std::sqrt;
  const double s = o.rate_scale;
  const T rate2 = gdot2 * (s * s) / (Gamma * Gamma) + o.rate_floor * o.rate_floor;
  const T x = pow(rate2, 0.5 * o.m);  // gdot_dim^m
  return (1.0 + o.theta1() * x) / (1.0 + o.theta2 * x);
}

// The conformation tensor as the constitutive equation sees it: in-plane components and zz.
template <class T>
struct Conformation {
  T xx, xy, yy, zz;
};

// A law at one state M: P(M) = k0 I + k1 M + k2 M^2 and tau_p = modulus (s0 I + s1 M) (table
// above); `factor` is f (FENE-P, FENE-CR) or Y (PTT), 1 otherwise, and the state is admissible
// only where it is positive (tr M < 3b; a linear PTT's Y > 0). quadratic: k2 is part of the law
// (Giesekus), decided by the law and not by k2's value, so that dP/dalpha at alpha = 0 is kept.
template <class T>
struct Relaxation {
  T k0, k1, k2, s0, s1, factor;
  bool quadratic = false;
};

// The law's terms at M; dynamic_zz: M.zz is FENE-P's unknown M_zz (else f M_zz = 1 eliminates it;
// the other laws always read M.zz, which is 1 where it is not an unknown).
template <class T, class P>
Relaxation<T> relaxation(FluidModel model, bool dynamic_zz, const Conformation<T>& M, const LawConstants<P>& c) {
  using std::exp;
  switch (model) {
    case FluidModel::FeneP: {
      const T f = dynamic_zz ? peterlin_full(M.xx, M.yy, M.zz, c.b) : peterlin_eliminated(M.xx, M.yy, c.b);
      return {T(-1.0), f, T(0.0), T(-1.0), f, f};
    }
    case FluidModel::FeneCr: {
      const T f = peterlin_full(M.xx, M.yy, M.zz, c.b);
      const T mf = -f;
      return {mf, f, T(0.0), mf, f, f};
    }
    case FluidModel::Giesekus: {
      const T k0 = c.alpha - 1.0, k1 = 1.0 - 2.0 * c.alpha, k2 = c.alpha;
      return {k0, k1, k2, T(-1.0), T(1.0), T(1.0), true};
    }
    case FluidModel::PttLinear:
    case FluidModel::PttExponential: {
      const T x = c.epsilon * (M.xx + M.yy + M.zz - 3.0);
      const T Y = model == FluidModel::PttLinear ? T(1.0 + x) : T(exp(x));
      const T mY = -Y;
      return {mY, Y, T(0.0), T(-1.0), T(1.0), Y};
    }
    default: return {T(-1.0), T(1.0), T(0.0), T(-1.0), T(1.0), T(1.0)};
  }
}

// Why a state is not admissible for the law (its factor is not positive): a sentence, or null
// for laws whose factor is always 1.
const char* inadmissible_state(FluidModel model);

// P(M) = k0 I + k1 M + k2 M^2 (components xx, xy, yy, zz).
template <class T>
Conformation<T> relaxation_tensor(const Conformation<T>& M, const Relaxation<T>& k) {
  Conformation<T> p{k.k0 + k.k1 * M.xx, k.k1 * M.xy, k.k0 + k.k1 * M.yy, k.k0 + k.k1 * M.zz};
  if (k.quadratic) {
    const T xy2 = M.xy * M.xy;
    p.xx = p.xx + k.k2 * (M.xx * M.xx + xy2);
    p.xy = p.xy + k.k2 * (M.xy * (M.xx + M.yy));
    p.yy = p.yy + k.k2 * (xy2 + M.yy * M.yy);
    p.zz = p.zz + k.k2 * (M.zz * M.zz);
  }
  return p;
}

// The upper-convected stretch L M + M L^T of the in-plane components, and 2 Lzz M_zz.
template <class T, class G, class Z>
Conformation<T> convected_stretch(const Conformation<T>& M, const G (&L)[2][2], const Z& Lzz) {
  const T sxx = 2.0 * (L[0][0] * M.xx + L[0][1] * M.xy);
  const T sxy = L[0][0] * M.xy + L[0][1] * M.yy + M.xx * L[1][0] + M.xy * L[1][1];
  const T syy = 2.0 * (L[1][0] * M.xy + L[1][1] * M.yy);
  const T szz = 2.0 * Lzz * M.zz;
  return {sxx, sxy, syy, szz};
}

// The stretch with the Gordon-Schowalter slip xi: L_e M + M L_e^T + 2 xi D, L_e = L - xi D.
template <class T, class G, class X, class Z>
Conformation<T> slip_stretch(const Conformation<T>& M, const G (&L)[2][2], const X& xi, const Z& Lzz) {
  const T dxy = 0.5 * (L[0][1] + L[1][0]);
  const T Le[2][2] = {{L[0][0] - xi * L[0][0], L[0][1] - xi * dxy}, {L[1][0] - xi * dxy, L[1][1] - xi * L[1][1]}};
  const T Lzz_e = Lzz - xi * Lzz;
  Conformation<T> s = convected_stretch(M, Le, Lzz_e);
  s.xx = s.xx + 2.0 * xi * L[0][0];
  s.xy = s.xy + 2.0 * xi * dxy;
  s.yy = s.yy + 2.0 * xi * L[1][1];
  s.zz = s.zz + 2.0 * xi * Lzz;
  return s;
}

// The constitutive rate without convection, R = -(L M + M L^T) + P(M) / lambda_eff (components
// xx, xy, yy, zz); a steady homogeneous state has R = 0. L[i][j] = d v_i / d x_j in the plane,
// Lzz = d v_z / d z (0 in planar flow, -eps/2 in uniaxial extension). xi: PTT's slip (null for
// the upper-convected derivative), the stretch then slip_stretch's.
template <class T, class G, class I, class X = double, class Z = double>
Conformation<T> conformation_rate(const Conformation<T>& M, const G (&L)[2][2], const Relaxation<T>& k,
                                  const I& inv_lambda, const X* xi = nullptr, const Z& Lzz = 0.0) {
  const Conformation<T> s = xi ? slip_stretch(M, L, *xi, Lzz) : convected_stretch(M, L, Lzz);
  const Conformation<T> p = relaxation_tensor(M, k);
  return {inv_lambda * p.xx - s.xx, inv_lambda * p.xy - s.xy, inv_lambda * p.yy - s.yy, inv_lambda * p.zz - s.zz};
}

// Polymer stress tau_p = modulus (s0 I + s1 M), modulus = (1 - beta) Gamma / Wi.
template <class T, class P>
Conformation<T> polymer_stress(const Conformation<T>& M, const Relaxation<T>& k, const P& modulus) {
  return {modulus * (k.s0 + k.s1 * M.xx), modulus * (k.s1 * M.xy), modulus * (k.s0 + k.s1 * M.yy),
          modulus * (k.s0 + k.s1 * M.zz)};
}

}  // namespace keller
