// The 2x2 symmetric matrix algebra of the log-conformation formulation (Fattal and Kupferman),
// written through invariants only so that it is smooth, and dual numbers give exact Jacobians,
// where the eigenvalues coincide (M = I at rest and at inflow walls' corners):
//
//   Psi = a I + N (N traceless), rho^2 = -det N,  exp(Psi) = e^a (cosh rho I + sinh(rho)/rho N),
//   and the term (Omega Psi - Psi Omega) + 2 B of the decomposition of the velocity gradient L,
//   T = 1/2 (1 + rho coth rho) S + 1/2 G(rho^2) N S N + 1/2 (W N - N W),
//   S = L + L^T, W = L - L^T, G = (1 - rho coth rho) / rho^2,
// derived from the eigenbasis form with the projectors P = (I -+ N/rho)/2; every rho-dependent
// factor is a function of rho^2 evaluated by its Taylor series near 0. The log-conformation
// equation is v . grad Psi - T = -(1/lambda) P(M) M^-1 (FENE-P: (1/lambda) (exp(-Psi) - f I)).
#pragma once

#include <cmath>

#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

template <class T>
struct Sym2 {
  T xx, xy, yy;
};

namespace logconf {

// Even functions of rho as functions of x = rho^2.
template <class T>
T cosh_even(const T& x) {  // cosh(rho)
  using std::cosh;
  using std::sqrt;
  if (x < 1e-3) return 1.0 + x * (1.0 / 2 + x * (1.0 / 24 + x * (1.0 / 720 + x * (1.0 / 40320 + x / 3628800))));
  return cosh(sqrt(x));
}
template <class T>
T sinhc_even(const T& x) {  // sinh(rho) / rho
  using std::sinh;
  using std::sqrt;
  if (x < 1e-3) return 1.0 + x * (1.0 / 6 + x * (1.0 / 120 + x * (1.0 / 5040 + x * (1.0 / 362880 + x / 39916800))));
  const T r = sqrt(x);
  return sinh(r) / r;
}
template <class T>
T rcoth_even(const T& x) {  // rho coth rho = 1 + x/3 - x^2/45 + 2x^3/945 - x^4/4725 + ...
  using std::sqrt;
  using std::tanh;
  if (x < 1e-3) return 1.0 + x * (1.0 / 3 + x * (-1.0 / 45 + x * (2.0 / 945 + x * (-1.0 / 4725))));
  const T r = sqrt(x);
  return r / tanh(r);
}
template <class T>
T g_even(const T& x) {  // (1 - rho coth rho) / rho^2 = -1/3 + x/45 - 2x^2/945 + x^3/4725 - ...
  if (x < 1e-3) return -1.0 / 3 + x * (1.0 / 45 + x * (-2.0 / 945 + x * (1.0 / 4725 - x * 2.0 / 93555)));
  return (1.0 - rcoth_even(x)) / x;
}

}  // namespace logconf

// exp of a symmetric 2x2 matrix.
template <class T>
Sym2<T> sym_exp(const Sym2<T>& p) {
  using std::exp;
  const T a = 0.5 * (p.xx + p.yy), d = 0.5 * (p.xx - p.yy);
  const T x = d * d + p.xy * p.xy;
  const T e = exp(a), c = e * logconf::cosh_even(x), s = e * logconf::sinhc_even(x);
  return {c + s * d, s * p.xy, c - s * d};
}

// T = (Omega Psi - Psi Omega) + 2 B for the velocity gradient L (L[i][j] = d v_i / d x_j).
template <class T, class G>
Sym2<T> log_conformation_stretch(const Sym2<T>& p, const G (&L)[2][2]) {
  const T d = 0.5 * (p.xx - p.yy), c = p.xy;  // N = [[d, c], [c, -d]]
  const T x = d * d + c * c;
  const T h = 0.5 * (1.0 + logconf::rcoth_even(x)), g = 0.5 * logconf::g_even(x);
  const G s00 = 2.0 * L[0][0], s01 = L[0][1] + L[1][0], s11 = 2.0 * L[1][1];
  const G w = L[0][1] - L[1][0];  // W = [[0, w], [-w, 0]]
  // N S N for N = [[d, c], [c, -d]] and symmetric S
  const T ns00 = d * s00 + c * s01, ns01 = d * s01 + c * s11, ns10 = c * s00 - d * s01, ns11 = c * s01 - d * s11;
  const T nsn00 = ns00 * d + ns01 * c, nsn01 = ns00 * c - ns01 * d, nsn11 = ns10 * c - ns11 * d;
  // W N - N W = w [[2c, -2d], [-2d, -2c]]
  return {h * s00 + g * nsn00 + w * c, h * s01 + g * nsn01 - w * d, h * s11 + g * nsn11 - w * c};
}

// The log-conformation equation without convection, in-plane part, for a law with
// P(M) = k0 I + k1 M + k2 M^2 (ConstitutiveLaw.hpp): P commutes with M, so its part of the Psi
// equation is P(M) M^-1 = k0 M^-1 + k1 I + k2 M, and
// R = -T(L, Psi) + (k0 exp(-Psi) + k1 I + k2 M) / lambda_eff; a steady homogeneous state has
// R = 0. M = exp(Psi) is read only for a quadratic law (Giesekus).
template <class T, class G, class I>
Sym2<T> log_conformation_rate(const Sym2<T>& psi, const G (&L)[2][2], const Relaxation<T>& k, const Sym2<T>& M,
                              const I& inv_lambda) {
  const Sym2<T> st = log_conformation_stretch(psi, L);
  const Sym2<T> minv = sym_exp(Sym2<T>{-psi.xx, -psi.xy, -psi.yy});
  T pxx = k.k0 * minv.xx + k.k1, pxy = k.k0 * minv.xy, pyy = k.k0 * minv.yy + k.k1;
  if (k.quadratic) {
    pxx = pxx + k.k2 * M.xx;
    pxy = pxy + k.k2 * M.xy;
    pyy = pyy + k.k2 * M.yy;
  }
  return {inv_lambda * pxx - st.xx, inv_lambda * pxy - st.xy, inv_lambda * pyy - st.yy};
}

// The zz component of the log form, psi_zz = log M_zz (an eigendirection in planar flow, and in
// uniaxial extension along x): R = -2 Lzz + (k0 exp(-psi_zz) + k1 + k2 M_zz) / lambda_eff.
template <class T, class I, class Z = double>
T log_conformation_rate_zz(const T& psi_zz, const Relaxation<T>& k, const T& Mzz, const I& inv_lambda,
                           const Z& Lzz = 0.0) {
  using std::exp;
  T p = k.k0 * exp(-psi_zz) + k.k1;
  if (k.quadratic) p = p + k.k2 * Mzz;
  return inv_lambda * p - 2.0 * Lzz;
}

// log of a symmetric positive definite 2x2 matrix (double; for boundary values and output).
Sym2<double> sym_log(const Sym2<double>& m);

}  // namespace keller
