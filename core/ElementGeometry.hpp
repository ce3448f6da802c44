// Isoparametric geometry of a 9-node element at its Gauss points, templated on the scalar type
// of the node positions: double for a fixed mesh (computed once and cached), a dual number when
// node positions are unknowns or depend on a geometric parameter (shape derivatives).
#pragma once

#include <array>
#include <cmath>

#include "core/ReferenceElement.hpp"

namespace keller {

// Geometry at one Gauss point of the element interior.
template <class G>
struct QpGeometry {
  G x[2];         // physical position
  G detJ;         // det(dx/ds)
  G wdetJ;        // Gauss weight * detJ: the area element
  G dN2dx[9][2];  // Q2 shape-function gradients in physical coordinates
  G dN1dx[4][2];  // Q1 shape-function gradients in physical coordinates
};

// Geometry at one Gauss point of an element edge.
template <class G>
struct EdgeQpGeometry {
  G x[2];         // physical position
  G normal[2];    // outward unit normal
  G wds;          // Gauss weight * |dx/ds| along the edge: the line element
  G dN2dx[9][2];  // Q2 gradients in physical coordinates at this point
};

using ElementNodes = std::array<std::array<double, 2>, 9>;

namespace detail {

template <class G>
inline void inverse_jacobian(const double dN[9][2], const G (&xy)[9][2], G Jinv[2][2], G& det) {
  G J00 = 0.0, J01 = 0.0, J10 = 0.0, J11 = 0.0;  // J_ij = d x_i / d s_j
  for (int a = 0; a < 9; ++a) {
    J00 += xy[a][0] * dN[a][0];
    J01 += xy[a][0] * dN[a][1];
    J10 += xy[a][1] * dN[a][0];
    J11 += xy[a][1] * dN[a][1];
  }
  det = J00 * J11 - J01 * J10;
  const G inv = 1.0 / det;
  Jinv[0][0] = J11 * inv;   // d s / d x
  Jinv[0][1] = -J01 * inv;  // d s / d y
  Jinv[1][0] = -J10 * inv;  // d t / d x
  Jinv[1][1] = J00 * inv;   // d t / d y
}

}  // namespace detail

// Maps the 3x3 Gauss points of an element with node positions xy. Returns false when
// det J <= 0 at some Gauss point (an inverted or degenerate element); out is then incomplete.
template <class G>
bool map_element(const G (&xy)[9][2], std::array<QpGeometry<G>, ref::kQp>& out) {
  const ref::Tables& tb = ref::tables();
  for (int q = 0; q < ref::kQp; ++q) {
    QpGeometry<G>& g = out[q];
    G Jinv[2][2];
    detail::inverse_jacobian(tb.dN2[q], xy, Jinv, g.detJ);
    if (!(g.detJ > 0.0)) return false;
    g.wdetJ = g.detJ * tb.w[q];
    g.x[0] = 0.0;
    g.x[1] = 0.0;
    for (int a = 0; a < 9; ++a) {
      g.x[0] += xy[a][0] * tb.N2[q][a];
      g.x[1] += xy[a][1] * tb.N2[q][a];
      for (int i = 0; i < 2; ++i) g.dN2dx[a][i] = tb.dN2[q][a][0] * Jinv[0][i] + tb.dN2[q][a][1] * Jinv[1][i];
    }
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 2; ++i) g.dN1dx[k][i] = tb.dN1[q][k][0] * Jinv[0][i] + tb.dN1[q][k][1] * Jinv[1][i];
  }
  return true;
}

// Maps the 3 Gauss points of edge e (0 bottom, 1 right, 2 top, 3 left) of an element with
// node positions xy. Assumes the element is positively oriented (det J > 0).
template <class G>
bool map_edge(const G (&xy)[9][2], int e, std::array<EdgeQpGeometry<G>, ref::kEdgeQp>& out) {
  using std::sqrt;
  const ref::Tables& tb = ref::tables();
  const int dir = (e == 0 || e == 2) ? 0 : 1;  // edge runs along s (bottom, top) or t
  const double sign = (e == 0 || e == 1) ? 1.0 : -1.0;
  for (int k = 0; k < ref::kEdgeQp; ++k) {
    EdgeQpGeometry<G>& g = out[k];
    G Jinv[2][2], det;
    detail::inverse_jacobian(tb.edge_dN2[e][k], xy, Jinv, det);
    if (!(det > 0.0)) return false;
    G tx = 0.0, ty = 0.0;
    g.x[0] = 0.0;
    g.x[1] = 0.0;
    for (int a = 0; a < 9; ++a) {
      tx += xy[a][0] * tb.edge_dN2[e][k][a][dir];
      ty += xy[a][1] * tb.edge_dN2[e][k][a][dir];
      g.x[0] += xy[a][0] * tb.edge_N2[e][k][a];
      g.x[1] += xy[a][1] * tb.edge_N2[e][k][a];
      for (int i = 0; i < 2; ++i)
        g.dN2dx[a][i] = tb.edge_dN2[e][k][a][0] * Jinv[0][i] + tb.edge_dN2[e][k][a][1] * Jinv[1][i];
    }
    const G len = sqrt(tx * tx + ty * ty);
    g.wds = len * tb.edge_w[k];
    g.normal[0] = sign * ty / len;
    g.normal[1] = -sign * tx / len;
  }
  return true;
}

}  // namespace keller
