// The reference 9-node quadrilateral [-1,1]^2: node ordering, Q2 and Q1 shape functions, the
// 3x3 Gauss rule, the 3-point edge rule, and the values of all of these tabulated once.
//
// Node ordering is lexicographic: node a = i + 3 j has reference coordinates
// (s_i, t_j) with s, t in {-1, 0, 1}. Vertices are nodes 0, 2, 6, 8; the Q1 basis lives on them
// in the same lexicographic order (Q1 local index k = i + 2 j -> node q1_node[k]).
// Edges: 0 bottom (t = -1: nodes 0 1 2), 1 right (s = 1: 2 5 8), 2 top (t = 1: 6 7 8),
// 3 left (s = -1: 0 3 6); each lists its nodes in increasing s or t.
#pragma once

#include <array>

namespace keller::ref {

inline constexpr int kNodes = 9;
inline constexpr int kVertices = 4;
inline constexpr int kQp = 9;      // 3x3 Gauss points
inline constexpr int kEdgeQp = 3;  // 3-point Gauss rule on an edge

inline constexpr std::array<int, 4> q1_node = {0, 2, 6, 8};
inline constexpr std::array<std::array<int, 3>, 4> edge_nodes = {{{0, 1, 2}, {2, 5, 8}, {6, 7, 8}, {0, 3, 6}}};

// 1D quadratic Lagrange polynomials on nodes -1, 0, 1 and their derivatives.
inline double lagrange2(int i, double x) {
  switch (i) {
    case 0: return 0.5 * x * (x - 1.0);
    case 1: return 1.0 - x * x;
    default: return 0.5 * x * (x + 1.0);
  }
}
inline double lagrange2_d(int i, double x) {
  switch (i) {
    case 0: return x - 0.5;
    case 1: return -2.0 * x;
    default: return x + 0.5;
  }
}
inline double lagrange1(int i, double x) { return i == 0 ? 0.5 * (1.0 - x) : 0.5 * (1.0 + x); }
inline double lagrange1_d(int i, double) { return i == 0 ? -0.5 : 0.5; }

// Shape functions at an arbitrary reference point.
void q2_shape(double s, double t, double N[9], double dN[9][2]);
void q1_shape(double s, double t, double N[4], double dN[4][2]);

// Reference coordinates of node a.
inline double node_s(int a) { return static_cast<double>(a % 3) - 1.0; }
inline double node_t(int a) { return static_cast<double>(a / 3) - 1.0; }

// Everything evaluated at the 3x3 Gauss points (q = i + 3 j, lexicographic like the nodes).
struct Tables {
  double s[kQp], t[kQp], w[kQp];
  double N2[kQp][9], dN2[kQp][9][2];
  double N1[kQp][4], dN1[kQp][4][2];
  // Edge rule: reference point, weight (on [-1,1]) and Q2/Q1 values at edge Gauss point g of edge e.
  double edge_s[4][kEdgeQp], edge_t[4][kEdgeQp], edge_w[kEdgeQp];
  double edge_N2[4][kEdgeQp][9], edge_dN2[4][kEdgeQp][9][2];
  double edge_N1[4][kEdgeQp][4];
};

const Tables& tables();

}  // namespace keller::ref
