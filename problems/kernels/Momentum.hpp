// The momentum and continuity terms of incompressible flow at one Gauss point, written once for
// every fluid (the Newtonian and the viscoelastic kernels assemble them; post-processing
// evaluates the same stress). Q2 velocity, P1-discontinuous pressure in physical coordinates
// psi = (1, x - xc, y - yc) about the element's centre node; K_ij = d v_i / d x_j.
//
//   momentum    R_ai = int [ phi_a (rho (v . grad v)_i - f_i) + dphi_a/dx_j T_ij ] dA
//   continuity  R_k  = - int psi_k div v dA
// with rho = Re / Gamma, a body force f (FlowSource.hpp, manufactured solutions only) and the
// total stress T = -P I + beta (K + K^T) + the fluid's extra terms (DEVSS, tau_p). The
// time-dependent form adds rho int phi_a dv_i/dt, the rate at a fixed point of space: on a mesh
// whose nodes move at xdot (ALE) that is the nodal rate minus xdot . grad v_i.
// Local rows: v_x at nodes 0..8, v_y at nodes 0..8, then the 3 pressure coefficients.
#pragma once

#include "core/AutoDiff.hpp"
#include "core/ElementGeometry.hpp"
#include "core/ReferenceElement.hpp"
#include "problems/kernels/FlowSource.hpp"

namespace keller {

// A symmetric in-plane stress (or any symmetric 2x2 tensor).
template <class T>
struct PlaneStress {
  T xx, xy, yy;
};

// Velocity and its gradient at a Gauss point: v = sum N_a v_a, K = sum v_a (dN_a/dx)^T.
template <class T>
struct VelocityAt {
  T v[2];
  T K[2][2];
  T divergence() const { return K[0][0] + K[1][1]; }
};

// The velocity gradient from Q2 shape-function gradients dN (element or edge Gauss point).
template <class T, class D>
void velocity_gradient(const T* vx, const T* vy, const D (&dN)[9][2], T (&K)[2][2]) {
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) K[i][j] = 0.0;
  for (int a = 0; a < 9; ++a)
    for (int j = 0; j < 2; ++j) {
      K[0][j] += dN[a][j] * vx[a];
      K[1][j] += dN[a][j] * vy[a];
    }
}

template <class T, class G>
VelocityAt<T> velocity_at(const T* vx, const T* vy, int q, const QpGeometry<G>& g) {
  const ref::Tables& tb = ref::tables();
  VelocityAt<T> s;
  s.v[0] = 0.0;
  s.v[1] = 0.0;
  for (int a = 0; a < 9; ++a) {
    s.v[0] += tb.N2[q][a] * vx[a];
    s.v[1] += tb.N2[q][a] * vy[a];
  }
  velocity_gradient(vx, vy, g.dN2dx, s.K);
  return s;
}

// The P1-discontinuous pressure basis at position x of an element with centre node c.
template <class G, class C>
void pressure_basis(const G (&x)[2], const C (&c)[2], G (&psi)[3]) {
  psi[0] = G(1.0);
  psi[1] = x[0] - c[0];
  psi[2] = x[1] - c[1];
}

template <class T, class G>
T pressure_at(const T* pc, const G (&psi)[3]) {
  return pc[0] + psi[1] * pc[1] + psi[2] * pc[2];
}

// The Newtonian (solvent) viscous stress beta (K + K^T).
template <class T, class P>
PlaneStress<T> viscous_stress(const P& beta, const T (&K)[2][2]) {
  return {2.0 * beta * K[0][0], beta * (K[0][1] + K[1][0]), 2.0 * beta * K[1][1]};
}

// The momentum load rho (v . grad v) - f at a Gauss point at position x; rho = 0 without inertia.
template <class T, class P, class G>
void momentum_load(const VelocityAt<T>& s, bool inertia, const P& rho, const FlowSource* source, const G (&x)[2],
                   T (&load)[2]) {
  load[0] = 0.0;
  load[1] = 0.0;
  if (inertia) {
    load[0] = rho * (s.v[0] * s.K[0][0] + s.v[1] * s.K[0][1]);
    load[1] = rho * (s.v[0] * s.K[1][0] + s.v[1] * s.K[1][1]);
  }
  if (source && source->momentum) {
    const double at[2] = {value_of(x[0]), value_of(x[1])};
    double f[2];
    source->momentum(at, f);
    load[0] -= f[0];
    load[1] -= f[1];
  }
}

// Adds the Gauss point's momentum rows (r[0..17]) for total stress T = Tn - P I (Tn: the
// stress without the pressure) and its continuity rows (r[18..20]).
template <class T, class G>
void add_momentum_continuity(int q, const QpGeometry<G>& g, const G (&psi)[3], const VelocityAt<T>& s,
                             const T (&load)[2], const PlaneStress<T>& Tn, const T& pressure, T* r) {
  const ref::Tables& tb = ref::tables();
  const T Txx = Tn.xx - pressure, Tyy = Tn.yy - pressure;
  const G w = g.wdetJ;
  for (int a = 0; a < 9; ++a) {
    const double N = tb.N2[q][a];
    const G dx = g.dN2dx[a][0], dy = g.dN2dx[a][1];
    r[a] += w * (N * load[0] + dx * Txx + dy * Tn.xy);
    r[9 + a] += w * (N * load[1] + dx * Tn.xy + dy * Tyy);
  }
  const T div = s.divergence();
  for (int k = 0; k < 3; ++k) r[18 + k] -= (w * psi[k]) * div;
}

// Adds a stress's divergence-form momentum rows int dphi_a/dx_j S_ij dA at a Gauss point
// (r[0..17]): a further polymer mode's stress, whose pressure, load and continuity rows are the
// first mode's kernel's.
template <class T, class G>
void add_stress_divergence(const QpGeometry<G>& g, const PlaneStress<T>& S, T* r) {
  const G w = g.wdetJ;
  for (int a = 0; a < 9; ++a) {
    const G dx = g.dN2dx[a][0], dy = g.dN2dx[a][1];
    r[a] += w * (dx * S.xx + dy * S.xy);
    r[9 + a] += w * (dx * S.xy + dy * S.yy);
  }
}

// The rate of a Q2 field component (nodal rates fdot, 9 entries) at Gauss point q as seen at a
// fixed point of space: sum N_a fdot_a - xdot . grad f, where the mesh moves at xdot (ALE; null:
// a fixed mesh) and grad f is the field's gradient there.
template <class W>
W q2_rate(int q, const W* fdot, const double (&grad)[2], const W* xdot) {
  const ref::Tables& tb = ref::tables();
  W rate = 0.0;
  for (int a = 0; a < 9; ++a) rate += tb.N2[q][a] * fdot[a];
  if (xdot) rate -= xdot[0] * grad[0] + xdot[1] * grad[1];
  return rate;
}

// The mesh velocity at Gauss point q from the nodal rates of the Q2 positions (x of nodes 0..8,
// then y), interpolated like the geometry.
template <class W>
void mesh_velocity(int q, const W* xdot_nodes, W (&xdot)[2]) {
  const ref::Tables& tb = ref::tables();
  xdot[0] = 0.0;
  xdot[1] = 0.0;
  for (int a = 0; a < 9; ++a) {
    xdot[0] += tb.N2[q][a] * xdot_nodes[a];
    xdot[1] += tb.N2[q][a] * xdot_nodes[9 + a];
  }
}

// The velocity rows' time terms rho int phi_a dv_i/dt at Gauss point q (r[0..17]), with
// dv_i/dt at a fixed point = q2_rate (the velocity's rates vdot: x of nodes 0..8, then y; the
// mesh velocity xdot at q, or null on a fixed mesh; K the velocity gradient there).
template <class W>
void add_velocity_rate(int q, double rho_wdetJ, const W* vdot, const double (&K)[2][2], const W* xdot, W* r) {
  const ref::Tables& tb = ref::tables();
  const double gx[2] = {K[0][0], K[0][1]}, gy[2] = {K[1][0], K[1][1]};
  const W ax = q2_rate(q, vdot, gx, xdot), ay = q2_rate(q, vdot + 9, gy, xdot);
  for (int a = 0; a < 9; ++a) {
    const double m = rho_wdetJ * tb.N2[q][a];
    r[a] += m * ax;
    r[9 + a] += m * ay;
  }
}

}  // namespace keller
