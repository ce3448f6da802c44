// Bratu problems at fixed lambda: the discretisation error falls at the order the method
// promises. 1D: central differences, max nodal error O(h^2) against the exact solution.
// 2D: Q2 elements, L2 error against a reference solution on a 4x finer mesh (error about 50x
// smaller than the finest tested mesh's). The source lambda e^u equals lambda != 0 at the four
// corners, so the solution carries the corner singularity r^2 log r (Grisvard) and Q2 gives
// O(h^3 log(1/h)) rather than O(h^3) in L2: observed orders rise towards 3 from below (2.59,
// 2.73, 2.80 for n = 4..32). The max nodal error is O(h^2), set at the corners.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "core/Newton.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Bratu2DProblem.hpp"

using namespace keller;

TEST(BratuConvergence, OneDimensionalSecondOrder) {
  const double lambda = 2.0;
  std::vector<double> err;
  for (int n : {16, 32, 64, 128}) {
    Bratu1DProblem p(n, lambda);
    Vector u = p.initial_guess();
    NewtonSolver newton(p);
    ASSERT_TRUE(newton.solve(u).converged());
    double e = 0;
    for (int i = 1; i < n; ++i) e = std::max(e, std::abs(u[i - 1] - Bratu1DProblem::exact(i * p.h(), lambda, false)));
    err.push_back(e);
    std::cout << "bratu1d n = " << n << ": max error " << e << "\n";
  }
  for (size_t k = 0; k + 1 < err.size(); ++k) {
    const double order = std::log2(err[k] / err[k + 1]);
    std::cout << "  observed order " << order << "\n";
    EXPECT_NEAR(order, 2.0, 0.05);
  }
}

TEST(BratuConvergence, TwoDimensionalQ2ThirdOrderInL2) {
  const double lambda = 5.0;
  auto solve = [&](int n) {
    auto p = std::make_unique<Bratu2DProblem>(n, lambda);
    Vector u = p->initial_guess();
    NewtonSolver newton(*p);
    EXPECT_TRUE(newton.solve(u).converged());
    return std::make_pair(std::move(p), u);
  };
  const int nref = 128;
  auto [ref, uref] = solve(nref);
  const ref::Tables& tb = ref::tables();
  std::vector<double> err;
  const std::vector<int> sizes = {4, 8, 16, 32};
  for (int n : sizes) {
    auto [p, u] = solve(n);
    // integrate (u_h - u_ref)^2 with the reference mesh's quadrature: each fine element lies in
    // one coarse element, so the integrand is smooth on it
    double e2 = 0;
    for (int e = 0; e < ref->mesh().num_elements(); ++e) {
      double xy[9][2];
      ref->mesh().element_nodes(e, xy);
      std::array<QpGeometry<double>, ref::kQp> g;
      map_element(xy, g);
      int d[9];
      ref->dofs().element_dofs(0, e, d);
      for (int q = 0; q < ref::kQp; ++q) {
        double ur = 0;
        for (int a = 0; a < 9; ++a) ur += tb.N2[q][a] * uref[d[a]];
        const double diff = p->evaluate(u, g[q].x[0], g[q].x[1]) - ur;
        e2 += g[q].wdetJ * diff * diff;
      }
    }
    err.push_back(std::sqrt(e2));
    std::cout << "bratu2d n = " << n << ": L2 error " << err.back() << "\n";
  }
  double previous = 0;
  for (size_t k = 0; k + 1 < err.size(); ++k) {
    const double order = std::log2(err[k] / err[k + 1]);
    std::cout << "  observed order " << order << "\n";
    EXPECT_GT(order, previous);  // rising towards 3 as the log factor fades
    EXPECT_GT(order, 2.5);
    EXPECT_LT(order, 3.05);
    previous = order;
  }
  for (size_t k = 0; k < err.size(); ++k) {
    const double h = 1.0 / sizes[k];
    std::cout << "  e / h^3 = " << err[k] / (h * h * h)
              << ", e / (h^3 log(1/h)) = " << err[k] / (h * h * h * std::log(1.0 / h)) << "\n";
  }
}
