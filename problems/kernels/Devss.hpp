// DEVSS-TG (method.md): the interpolated velocity gradient L (Q1, 4 components, not symmetric)
// and the stabilising stress it enters the momentum equation with,
//   beta_a ((K + K^T) - (L + L^T)),  beta_a = devss (or 1 - beta when negative),
// and the projection rows int chi [L - K + (div v / 2) I] (traceless in plane: tr I = 2).
// Local rows of the projection: L_xx, L_xy, L_yx, L_yy at the 4 Q1 nodes.
#pragma once

#include "core/ReferenceElement.hpp"
#include "problems/kernels/Momentum.hpp"

namespace keller {

// L at Gauss point q from its Q1 nodal values Lc = Lxx[4], Lxy[4], Lyx[4], Lyy[4].
template <class T>
void interpolated_gradient(const T* Lc, int q, T (&L)[2][2]) {
  const ref::Tables& tb = ref::tables();
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) L[i][j] = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double N = tb.N1[q][k];
    L[0][0] += N * Lc[k];
    L[0][1] += N * Lc[4 + k];
    L[1][0] += N * Lc[8 + k];
    L[1][1] += N * Lc[12 + k];
  }
}

template <class P>
P devss_viscosity(double devss, const P& beta) {
  return devss >= 0 ? P(devss) : P(1.0 - beta);
}

// The DEVSS stress beta_a ((K + K^T) - (L + L^T)) (xx, xy, yy).
template <class T, class P>
PlaneStress<T> devss_stress(const P& beta_a, const T (&K)[2][2], const T (&L)[2][2]) {
  return {2.0 * beta_a * (K[0][0] - L[0][0]), beta_a * ((K[0][1] + K[1][0]) - (L[0][1] + L[1][0])),
          2.0 * beta_a * (K[1][1] - L[1][1])};
}

// Adds the projection rows of Gauss point q (w: its area element) to r[0..15].
template <class T, class G>
void add_gradient_projection(int q, const G& w, const T (&K)[2][2], const T (&L)[2][2], T* r) {
  const ref::Tables& tb = ref::tables();
  const T div = K[0][0] + K[1][1];
  const T rl[4] = {L[0][0] - K[0][0] + 0.5 * div, L[0][1] - K[0][1], L[1][0] - K[1][0], L[1][1] - K[1][1] + 0.5 * div};
  for (int k = 0; k < 4; ++k)
    for (int c = 0; c < 4; ++c) r[4 * c + k] += (w * tb.N1[q][k]) * rl[c];
}

}  // namespace keller
