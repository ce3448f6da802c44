// Dual numbers: values and derivatives of every operation against closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "core/Dual.hpp"

using keller::Dual;
using keller::make_variable;

TEST(Dual, ArithmeticMatchesClosedForms) {
  const auto x = make_variable<2>(1.3, 0), y = make_variable<2>(-0.7, 1);
  const auto f = (x * y + 2.0 * x - y / x) / (1.0 + x * x);
  // f = (x y + 2 x - y / x) / (1 + x^2)
  const double X = 1.3, Y = -0.7, D = 1 + X * X, num = X * Y + 2 * X - Y / X;
  EXPECT_NEAR(f.v, num / D, 1e-15);
  const double dnum_dx = Y + 2 + Y / (X * X), dnum_dy = X - 1 / X;
  EXPECT_NEAR(f.d[0], (dnum_dx * D - num * 2 * X) / (D * D), 1e-14);
  EXPECT_NEAR(f.d[1], dnum_dy / D, 1e-14);
}

TEST(Dual, ElementaryFunctions) {
  const auto x = make_variable<1>(0.8, 0);
  EXPECT_NEAR(exp(x).d[0], std::exp(0.8), 1e-15);
  EXPECT_NEAR(log(x).d[0], 1 / 0.8, 1e-15);
  EXPECT_NEAR(sqrt(x).d[0], 0.5 / std::sqrt(0.8), 1e-15);
  EXPECT_NEAR(pow(x, 2.5).d[0], 2.5 * std::pow(0.8, 1.5), 1e-14);
  EXPECT_NEAR(tanh(x).d[0], 1 - std::tanh(0.8) * std::tanh(0.8), 1e-15);
  EXPECT_NEAR(sin(x).d[0], std::cos(0.8), 1e-15);
  EXPECT_NEAR(cos(x).d[0], -std::sin(0.8), 1e-15);
  EXPECT_NEAR((1.0 / x).d[0], -1 / 0.64, 1e-14);
  EXPECT_NEAR(abs(-x).d[0], 1.0, 0.0);
  const auto y = make_variable<1>(1.7, 0);
  // d/dy (y^y) = y^y (ln y + 1)
  EXPECT_NEAR(pow(y, y).d[0], std::pow(1.7, 1.7) * (std::log(1.7) + 1), 1e-13);
}

TEST(Dual, CompoundAssignmentAndComparison) {
  auto x = make_variable<3>(2.0, 2);
  x *= x;  // x^2
  x += 1.0;
  x /= 2.0;  // (x^2 + 1) / 2, derivative x = 2 at x = 2
  EXPECT_DOUBLE_EQ(x.v, 2.5);
  EXPECT_DOUBLE_EQ(x.d[2], 2.0);
  EXPECT_DOUBLE_EQ(x.d[0], 0.0);
  EXPECT_TRUE(x > 2.0);
  EXPECT_TRUE(1.0 < x);
  EXPECT_FALSE(keller::is_finite(Dual<1>(std::nan(""))));
}
