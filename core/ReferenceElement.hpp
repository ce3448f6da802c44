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
constexpr double lagrange2(int i, double x) {
  switch (i) {
    case 0: return 0.5 * x * (x - 1.0);
    case 1: return 1.0 - x * x;
    default: return 0.5 * x * (x + 1.0);
  }
}
constexpr double lagrange2_d(int i, double x) {
  switch (i) {
    case 0: return x - 0.5;
    case 1: return -2.0 * x;
    default: return x + 0.5;
  }
}
constexpr double lagrange1(int i, double x) { return i == 0 ? 0.5 * (1.0 - x) : 0.5 * (1.0 + x); }
constexpr double lagrange1_d(int i, double) { return i == 0 ? -0.5 : 0.5; }

// Shape functions at an arbitrary reference point.
constexpr void q2_shape(double s, double t, double N[9], double dN[9][2]) {
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      const int a = i + 3 * j;
      N[a] = lagrange2(i, s) * lagrange2(j, t);
      dN[a][0] = lagrange2_d(i, s) * lagrange2(j, t);
      dN[a][1] = lagrange2(i, s) * lagrange2_d(j, t);
    }
  }
}
constexpr void q1_shape(double s, double t, double N[4], double dN[4][2]) {
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      const int k = i + 2 * j;
      N[k] = lagrange1(i, s) * lagrange1(j, t);
      dN[k][0] = lagrange1_d(i, s) * lagrange1(j, t);
      dN[k][1] = lagrange1(i, s) * lagrange1_d(j, t);
    }
  }
}

// Reference coordinates of node a.
constexpr double node_s(int a) { return static_cast<double>(a % 3) - 1.0; }
constexpr double node_t(int a) { return static_cast<double>(a / 3) - 1.0; }

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

// The Gauss abscissa sqrt(3/5), as std::sqrt(0.6) gives it (written out: std::sqrt is not constexpr;
// ReferenceElement.GaussAbscissaIsTheSquareRootOfThreeFifths checks the digits).
inline constexpr double kGauss3 = 0.7745966692414834;

constexpr Tables build_tables() {
  Tables tb{};
  const double gp[3] = {-kGauss3, 0.0, kGauss3};
  const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      const int q = i + 3 * j;
      tb.s[q] = gp[i];
      tb.t[q] = gp[j];
      tb.w[q] = gw[i] * gw[j];
      q2_shape(tb.s[q], tb.t[q], tb.N2[q], tb.dN2[q]);
      q1_shape(tb.s[q], tb.t[q], tb.N1[q], tb.dN1[q]);
    }
  }
  for (int k = 0; k < 3; ++k) tb.edge_w[k] = gw[k];
  for (int e = 0; e < 4; ++e) {
    for (int k = 0; k < 3; ++k) {
      // bottom (t = -1), right (s = 1), top (t = 1), left (s = -1)
      const double s = e == 1 ? 1.0 : e == 3 ? -1.0 : gp[k];
      const double t = e == 0 ? -1.0 : e == 2 ? 1.0 : gp[k];
      tb.edge_s[e][k] = s;
      tb.edge_t[e][k] = t;
      q2_shape(s, t, tb.edge_N2[e][k], tb.edge_dN2[e][k]);
      double dN1[4][2]{};
      q1_shape(s, t, tb.edge_N1[e][k], dN1);
    }
  }
  return tb;
}

// The tables, computed by the compiler: the kernels' loops over them see constants (a function
// returning a static computed at first use cost a call and a guard at every Gauss point, and
// kept the compiler from assuming the tables unchanged across the kernels' writes).
inline constexpr Tables kTables = build_tables();
constexpr const Tables& tables() { return kTables; }

}  // namespace keller::ref
