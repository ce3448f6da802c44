// The exact derivatives of tests/support/ExactBrusselator.hpp against central differences of its
// residual (core/HigherDerivatives.hpp, force_differences) at a state that is not uniform, so that
// the Laplacian's terms count, along random directions with a change of each parameter in turn
// (a, b, D_u, D_v). The residual is cubic in the state and bilinear in (parameters, state), so the
// differences are exact but for rounding: eps S / h^2 at the D^2 step 1e-3 and eps S / h^3 at the
// D^3 step 1e-2, S the diffusion terms (D / dx^2 |w| = 64 |w| at 8 intervals): about 1e-8 of the
// derivatives; 1e-6 leaves room, and a wrong or missing term is an error of its own size.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/HigherDerivatives.hpp"
#include "support/ExactBrusselator.hpp"

using namespace keller;

TEST(ExactBrusselator, DerivativesAreTheLimitOfDifferencesAlongEveryParameter) {
  Brusselator1DOptions o;
  o.intervals = 8;
  o.a = 1.5;
  o.b = 3.2;
  o.D_u = 0.8;
  o.D_v = 1.3;
  test::ExactBrusselator problem(o);
  const int n = problem.size();
  Vector w(n), x(n), y(n), z(n);
  for (int i = 0; i < n; ++i) {  // smooth, not uniform
    w[i] = 2.0 + 0.3 * std::sin(1.3 * i) + (i % 2 ? 0.5 : 0.0);
    x[i] = std::cos(0.7 * i + 0.2);
    y[i] = std::sin(0.9 * i - 0.4);
    z[i] = std::cos(1.7 * i + 1.1);
  }
  for (int parameter = 0; parameter < 4; ++parameter) {
    HigherDerivatives exact(problem, parameter, w), differences(problem, parameter, w, true);
    ASSERT_EQ(exact.method(), HigherDerivatives::Method::Exact);
    ASSERT_EQ(differences.method(), HigherDerivatives::Method::Differences);
    const HigherDerivatives::Direction a{x, 0.7}, b{y, -0.4}, c{z};
    Vector e2, d2, e3, d3;
    ASSERT_TRUE(exact.second(a, b, e2).is_ok() && differences.second(a, b, d2).is_ok());
    ASSERT_TRUE(exact.third(a, b, c, e3).is_ok() && differences.third(a, b, c, d3).is_ok());
    EXPECT_GT(e2.norm(), 1.0) << parameter;
    EXPECT_LT((e2 - d2).norm(), 1e-6 * e2.norm()) << "D^2, parameter " << parameter;
    EXPECT_LT((e3 - d3).norm(), 1e-6 * e3.norm()) << "D^3, parameter " << parameter;
  }
  Vector out;
  const Vector u = Vector::Zero(n);
  EXPECT_FALSE(problem.directional_derivative(w, {{&u, nullptr}}, out).is_ok());  // order 1
}
