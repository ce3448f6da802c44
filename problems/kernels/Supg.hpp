// SUPG stabilisation of the constitutive equations (method.md): the test function chi of a
// conformation row becomes chi + tau v . grad chi, with the time scale tau written once for the
// residual and the mass matrix: local, tau = scale h_e / sqrt(|v|^2 + (floor Gamma)^2) with h_e
// = sqrt(element area), or global, tau = scale h_c / Gamma with h_c the mean element size.
#pragma once

#include <cmath>

#include "core/ElementGeometry.hpp"
#include "core/ReferenceElement.hpp"

namespace keller {

struct SupgOptions {
  bool local = true;  // tau = scale h_e / |v| (guarded), or global scale h_c / v_c
  double scale = 1.0;
  double velocity_floor = 1e-3;  // |v| is floored at this fraction of the velocity scale
  double global_size = 1.0;      // h_c for the global option
};

// tau at a point of velocity v in an element of size h; Gamma: the velocity scale.
template <class T, class G, class P>
T supg_time_scale(const SupgOptions& o, const G& h, const T (&v)[2], const P& Gamma) {
  using std::sqrt;
  if (o.local) {
    const P floor = o.velocity_floor * Gamma;
    return o.scale * h / sqrt(v[0] * v[0] + v[1] * v[1] + floor * floor);
  }
  return o.scale * o.global_size / Gamma;
}

// The SUPG-weighted test function of Q1 node k times the area element, w (chi_k + tau v . grad chi_k).
template <class T, class G>
T supg_weight(int q, int k, const QpGeometry<G>& g, const T& tau, const T (&v)[2]) {
  return g.wdetJ * (ref::tables().N1[q][k] + tau * (v[0] * g.dN1dx[k][0] + v[1] * g.dN1dx[k][1]));
}

}  // namespace keller
