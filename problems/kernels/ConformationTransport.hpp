// The constitutive equation of the viscoelastic fluids as a transport term at one Gauss point:
// the Q1 conformation M (xx, xy, yy, and zz where it is an unknown, NC = 4) or its logarithm
// Psi, convected by v and stretched by the interpolated velocity gradient L (Devss.hpp), for a
// law with relaxation P(M) = k0 I + k1 M + k2 M^2 (ConstitutiveLaw.hpp):
//   conformation  R = v . grad M - (L M + M L^T) + P(M) / lambda_eff   (PTT with xi: slip_stretch)
//   log form      R = v . grad Psi - T(L, Psi) + P(M) M^-1 / lambda_eff
//   zz (FENE-P)   R = v . grad M_zz + P_zz / lambda_eff,  log: + (k0 exp(-psi_zz) + k1) / lambda_eff
// with lambda_eff = lambda eta_p(gdot(L)) / eta_p0 for Owens, lambda otherwise. The rows are
// SUPG-weighted (Supg.hpp): int (chi + tau v . grad chi) [R - s] with an optional constitutive
// source s (manufactured solutions). Local rows: component c at Q1 node k is row 4 c + k. The
// time-dependent form adds the same weight times dM/dt at a fixed point of space (ALE on a moving
// mesh); the weight keeps the fluid velocity v, a Petrov-Galerkin choice consistent for any weight.
#pragma once

#include <cmath>

#include "core/AutoDiff.hpp"
#include "core/ElementGeometry.hpp"
#include "core/ReferenceElement.hpp"
#include "problems/kernels/FlowSource.hpp"
#include "problems/kernels/Supg.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/LogConformation.hpp"

namespace keller {

// The conformation tensor from its unknowns at a point: M itself, or exp(Psi) in the log form;
// M_zz = 1 unless it is an unknown (NC = 4).
template <int NC, class T>
Conformation<T> conformation_of(const T* m, bool log_form) {
  Conformation<T> M{m[0], m[1], m[2], T(1.0)};
  if (log_form) {
    const Sym2<T> E = sym_exp(Sym2<T>{m[0], m[1], m[2]});
    M = {E.xx, E.xy, E.yy, T(1.0)};
  }
  if constexpr (NC == 4) {
    using std::exp;
    M.zz = log_form ? T(exp(m[3])) : m[3];
  }
  return M;
}

// The conformation unknowns at Gauss point q and their gradients, from the Q1 nodal values
// mc (component c at node k: mc[4 c + k]).
template <int NC, class T, class G>
struct ConformationAt {
  T m[NC];
  T dm[NC][2];

  ConformationAt(const T* mc, int q, const QpGeometry<G>& g) {
    const ref::Tables& tb = ref::tables();
    for (int c = 0; c < NC; ++c) {
      m[c] = 0.0;
      dm[c][0] = 0.0;
      dm[c][1] = 0.0;
    }
    for (int k = 0; k < 4; ++k) {
      const double N = tb.N1[q][k];
      for (int c = 0; c < NC; ++c) {
        m[c] += N * mc[4 * c + k];
        dm[c][0] += g.dN1dx[k][0] * mc[4 * c + k];
        dm[c][1] += g.dN1dx[k][1] * mc[4 * c + k];
      }
    }
  }
};

// 1 / lambda_eff: Gamma / Wi, divided by the Owens factor of gdot^2 = 2 D:D with D the
// symmetric part of L (and D_zz = Lzz, 0 in planar flow).
template <class T, class P, class Z = double>
T inverse_relaxation_time(FluidModel model, const P& lambda, const T (&L)[2][2], const P& Gamma,
                          const OwensParameters& owens, const Z& Lzz = 0.0) {
  T inv_lambda = 1.0 / lambda;
  if (model == FluidModel::Owens) {
    const T dxx = L[0][0], dyy = L[1][1], dxy = 0.5 * (L[0][1] + L[1][0]);
    const T gdot2 = 2.0 * (dxx * dxx + dyy * dyy + 2.0 * dxy * dxy) + 2.0 * Lzz * Lzz;
    inv_lambda = inv_lambda / owens_factor(gdot2, Gamma, owens);
  }
  return inv_lambda;
}

// The transport residual R of each component at a point (M: the conformation there, k the law's
// terms at M, xi PTT's slip or null); the constitutive source at position x is subtracted.
template <int NC, class T, class G, class X, class S>
void conformation_transport(const ConformationAt<NC, T, G>& c, const Conformation<T>& M, const T (&v)[2],
                            const T (&L)[2][2], const Relaxation<T>& k, const T& inv_lambda, bool log_form, const S* xi,
                            const FlowSource* source, const X (&x)[2], T (&R)[NC]) {
  const T(&m)[NC] = c.m;
  const T(&dm)[NC][2] = c.dm;
  T rate[4];
  if (log_form) {
    const Sym2<T> r = log_conformation_rate(Sym2<T>{m[0], m[1], m[2]}, L, k, Sym2<T>{M.xx, M.xy, M.yy}, inv_lambda);
    rate[0] = r.xx;
    rate[1] = r.xy;
    rate[2] = r.yy;
    if constexpr (NC == 4) rate[3] = log_conformation_rate_zz(m[3], k, M.zz, inv_lambda);
  } else {
    const Conformation<T> r = conformation_rate(M, L, k, inv_lambda, xi);
    rate[0] = r.xx;
    rate[1] = r.xy;
    rate[2] = r.yy;
    if constexpr (NC == 4) rate[3] = r.zz;
  }
  for (int i = 0; i < NC; ++i) R[i] = v[0] * dm[i][0] + v[1] * dm[i][1] + rate[i];
  if (source && source->constitutive) {
    const double at[2] = {value_of(x[0]), value_of(x[1])};
    double s[4] = {0.0, 0.0, 0.0, 0.0};
    source->constitutive(at, s);
    for (int i = 0; i < NC; ++i) R[i] -= s[i];
  }
}

// Adds the SUPG-weighted rows of Gauss point q to r[0 .. 4 NC - 1].
template <int NC, class T, class G>
void add_conformation_rows(int q, const QpGeometry<G>& g, const T& tau, const T (&v)[2], const T (&R)[NC], T* r) {
  for (int k = 0; k < 4; ++k) {
    const T weight = supg_weight(q, k, g, tau, v);
    for (int c = 0; c < NC; ++c) r[4 * c + k] += weight * R[c];
  }
}

// The conformation rows' time terms at Gauss point q (r: the first conformation row),
// int (chi_k + tau v . grad chi_k) dM_c/dt with dM_c/dt at a fixed point of space: the Q1
// interpolant of the nodal rates mdot (component c at node l: mdot[4 c + l]) minus xdot . grad M_c
// on a mesh moving at xdot (ALE; null: a fixed mesh). The same for the log form's Psi.
template <int NC, class W>
void add_conformation_rate(int q, const QpGeometry<double>& g, double tau, const double (&v)[2], const W* mdot,
                           const ConformationAt<NC, double, double>& c, const W* xdot, W* r) {
  const ref::Tables& tb = ref::tables();
  W rate[NC];
  for (int m = 0; m < NC; ++m) {
    rate[m] = 0.0;
    for (int l = 0; l < 4; ++l) rate[m] += tb.N1[q][l] * mdot[4 * m + l];
    if (xdot) rate[m] -= xdot[0] * c.dm[m][0] + xdot[1] * c.dm[m][1];
  }
  for (int k = 0; k < 4; ++k) {
    const double wk = supg_weight(q, k, g, tau, v);
    for (int m = 0; m < NC; ++m) r[4 * m + k] += wk * rate[m];
  }
}

}  // namespace keller
