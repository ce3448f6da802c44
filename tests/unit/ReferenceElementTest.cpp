// Reference element: shape-function identities and the exactness of the 3x3 Gauss rule.
#include <gtest/gtest.h>

#include <cmath>

#include "core/ReferenceElement.hpp"

namespace ref = keller::ref;

TEST(ReferenceElement, Q2IsNodalPartitionOfUnity) {
  for (int b = 0; b < 9; ++b) {
    double N[9], dN[9][2];
    ref::q2_shape(ref::node_s(b), ref::node_t(b), N, dN);
    for (int a = 0; a < 9; ++a) EXPECT_DOUBLE_EQ(N[a], a == b ? 1.0 : 0.0);
  }
  double N[9], dN[9][2];
  ref::q2_shape(0.3, -0.71, N, dN);
  double sum = 0, dsum0 = 0, dsum1 = 0, xs = 0;
  for (int a = 0; a < 9; ++a) {
    sum += N[a];
    dsum0 += dN[a][0];
    dsum1 += dN[a][1];
    xs += ref::node_s(a) * ref::node_s(a) * dN[a][0];  // d(s^2)/ds = 2 s
  }
  EXPECT_NEAR(sum, 1.0, 1e-15);
  EXPECT_NEAR(dsum0, 0.0, 1e-15);
  EXPECT_NEAR(dsum1, 0.0, 1e-15);
  EXPECT_NEAR(xs, 0.6, 1e-15);
}

TEST(ReferenceElement, Q1LivesOnVertices) {
  for (int k = 0; k < 4; ++k) {
    const int a = ref::q1_node[k];
    double N[4], dN[4][2];
    ref::q1_shape(ref::node_s(a), ref::node_t(a), N, dN);
    for (int m = 0; m < 4; ++m) EXPECT_DOUBLE_EQ(N[m], m == k ? 1.0 : 0.0);
  }
}

TEST(ReferenceElement, GaussRuleIntegratesDegreeFiveExactly) {
  const ref::Tables& tb = ref::tables();
  for (int p = 0; p <= 5; ++p) {
    for (int q = 0; q <= 5; ++q) {
      double sum = 0;
      for (int k = 0; k < ref::kQp; ++k) sum += tb.w[k] * std::pow(tb.s[k], p) * std::pow(tb.t[k], q);
      auto exact1d = [](int n) { return n % 2 ? 0.0 : 2.0 / (n + 1); };
      EXPECT_NEAR(sum, exact1d(p) * exact1d(q), 1e-14) << "s^" << p << " t^" << q;
    }
  }
  // and fails (as it must) for degree 6
  double s6 = 0;
  for (int k = 0; k < ref::kQp; ++k) s6 += tb.w[k] * std::pow(tb.s[k], 6);
  EXPECT_GT(std::abs(s6 - 2.0 * 2.0 / 7.0), 1e-3);
}

TEST(ReferenceElement, EdgeTablesLieOnTheirEdges) {
  const ref::Tables& tb = ref::tables();
  for (int e = 0; e < 4; ++e) {
    for (int k = 0; k < ref::kEdgeQp; ++k) {
      // shape functions of nodes off the edge vanish on it
      for (int a = 0; a < 9; ++a) {
        const bool on = a == ref::edge_nodes[e][0] || a == ref::edge_nodes[e][1] || a == ref::edge_nodes[e][2];
        if (!on) {
          EXPECT_NEAR(tb.edge_N2[e][k][a], 0.0, 1e-15);
        }
      }
    }
  }
}

// The tables are computed by the compiler, with the Gauss abscissa written out: it must be the
// double std::sqrt(0.6) gives, and the tables must be the shape functions at the points they name,
// to rounding: a run-time evaluation may fuse a product and a sum (-march=native contracts
// 1 - x * x into one rounding) where the compiler's constant evaluation rounds twice, 1 ulp apart.
TEST(ReferenceElement, GaussAbscissaIsTheSquareRootOfThreeFifths) {
  EXPECT_EQ(ref::kGauss3, std::sqrt(0.6));
  static_assert(ref::tables().w[4] == (8.0 / 9.0) * (8.0 / 9.0), "the tables are a compile-time constant");
  const ref::Tables& tb = ref::tables();
  for (int q = 0; q < ref::kQp; ++q) {
    double N[9], dN[9][2];
    ref::q2_shape(tb.s[q], tb.t[q], N, dN);
    for (int a = 0; a < 9; ++a) {
      EXPECT_NEAR(tb.N2[q][a], N[a], 1e-15);
      EXPECT_NEAR(tb.dN2[q][a][0], dN[a][0], 1e-15);
      EXPECT_NEAR(tb.dN2[q][a][1], dN[a][1], 1e-15);
    }
  }
}
