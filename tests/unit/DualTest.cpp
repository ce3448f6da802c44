// Automatic differentiation helpers and the elementary functions kernels use, against closed
// forms: a kernel's Jacobian is only as right as these.
#include <gtest/gtest.h>

#include <cmath>

#include "core/AutoDiff.hpp"

using keller::Dual;
using keller::make_variable;

TEST(AutoDiff, ArithmeticMatchesClosedForms) {
  const Dual<2> x = make_variable<2>(1.3, 0), y = make_variable<2>(-0.7, 1);
  const Dual<2> f = (x * y + 2.0 * x - y / x) / (1.0 + x * x);
  const double X = 1.3, Y = -0.7, D = 1 + X * X, num = X * Y + 2 * X - Y / X;
  EXPECT_NEAR(keller::value_of(f), num / D, 1e-15);
  const double dnum_dx = Y + 2 + Y / (X * X), dnum_dy = X - 1 / X;
  EXPECT_NEAR(f.derivatives()[0], (dnum_dx * D - num * 2 * X) / (D * D), 1e-14);
  EXPECT_NEAR(f.derivatives()[1], dnum_dy / D, 1e-14);
}

TEST(AutoDiff, ElementaryFunctions) {
  using std::exp, std::log, std::sqrt, std::pow, std::tanh, std::abs;
  const Dual<1> x = make_variable<1>(0.8, 0);
  EXPECT_NEAR(Dual<1>(exp(x)).derivatives()[0], std::exp(0.8), 1e-15);
  EXPECT_NEAR(Dual<1>(log(x)).derivatives()[0], 1 / 0.8, 1e-15);
  EXPECT_NEAR(Dual<1>(sqrt(x)).derivatives()[0], 0.5 / std::sqrt(0.8), 1e-15);
  EXPECT_NEAR(Dual<1>(pow(x, 2.5)).derivatives()[0], 2.5 * std::pow(0.8, 1.5), 1e-14);
  EXPECT_NEAR(Dual<1>(tanh(x)).derivatives()[0], 1 - std::tanh(0.8) * std::tanh(0.8), 1e-15);
  EXPECT_NEAR(Dual<1>(1.0 / x).derivatives()[0], -1 / 0.64, 1e-14);
  EXPECT_NEAR(Dual<1>(abs(-x)).derivatives()[0], 1.0, 0.0);
}

TEST(AutoDiff, ConstantsAndFiniteness) {
  const Dual<3> c = 2.5;  // a constant promotes with zero derivatives
  EXPECT_EQ(c.derivatives(), Eigen::Vector3d::Zero());
  Dual<3> x = make_variable<3>(2.0, 2);
  x = x * x;
  x += 1.0;
  EXPECT_DOUBLE_EQ(keller::value_of(x), 5.0);
  EXPECT_DOUBLE_EQ(x.derivatives()[2], 4.0);
  EXPECT_TRUE(x > 2.0);
  EXPECT_TRUE(keller::is_finite(x));
  EXPECT_FALSE(keller::is_finite(Dual<1>(std::nan(""))));
  EXPECT_FALSE(keller::is_finite(std::nan("")));
}
