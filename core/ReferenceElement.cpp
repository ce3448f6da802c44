#include "core/ReferenceElement.hpp"

#include <cmath>

namespace keller::ref {

void q2_shape(double s, double t, double N[9], double dN[9][2]) {
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      const int a = i + 3 * j;
      N[a] = lagrange2(i, s) * lagrange2(j, t);
      dN[a][0] = lagrange2_d(i, s) * lagrange2(j, t);
      dN[a][1] = lagrange2(i, s) * lagrange2_d(j, t);
    }
  }
}

void q1_shape(double s, double t, double N[4], double dN[4][2]) {
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      const int k = i + 2 * j;
      N[k] = lagrange1(i, s) * lagrange1(j, t);
      dN[k][0] = lagrange1_d(i, s) * lagrange1(j, t);
      dN[k][1] = lagrange1(i, s) * lagrange1_d(j, t);
    }
  }
}

namespace {

Tables build_tables() {
  Tables tb{};
  const double g = std::sqrt(0.6);
  const double gp[3] = {-g, 0.0, g};
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
  for (int g3 = 0; g3 < 3; ++g3) tb.edge_w[g3] = gw[g3];
  for (int e = 0; e < 4; ++e) {
    for (int k = 0; k < 3; ++k) {
      double s = 0, t = 0;
      switch (e) {
        case 0:
          s = gp[k];
          t = -1;
          break;
        case 1:
          s = 1;
          t = gp[k];
          break;
        case 2:
          s = gp[k];
          t = 1;
          break;
        default:
          s = -1;
          t = gp[k];
          break;
      }
      tb.edge_s[e][k] = s;
      tb.edge_t[e][k] = t;
      q2_shape(s, t, tb.edge_N2[e][k], tb.edge_dN2[e][k]);
      double dN1[4][2];
      q1_shape(s, t, tb.edge_N1[e][k], dN1);
    }
  }
  return tb;
}

}  // namespace

const Tables& tables() {
  static const Tables tb = build_tables();
  return tb;
}

}  // namespace keller::ref
