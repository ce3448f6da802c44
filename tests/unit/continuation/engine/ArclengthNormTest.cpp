// The arclength norm (continuation/engine/ArclengthNorm): its weights and constraints.
#include <gtest/gtest.h>

#include <stdexcept>

#include "continuation/engine/ArclengthNorm.hpp"

using namespace keller;

// The inner product and the constraints: the weights theta / (n s^2) and 1 - theta; the
// pseudo-arclength row measured from its point; the parameter row.
TEST(ArclengthNorm, WeightsAndConstraints) {
  const ArclengthNorm norm(4, 2.0, 0.5);
  EXPECT_DOUBLE_EQ(norm.wu(), 0.5 / (4 * 4.0));
  EXPECT_DOUBLE_EQ(norm.wl(), 0.5);
  const Vector u = Vector::Constant(4, 2.0);  // RMS 2: weighs like a parameter change of 1
  EXPECT_DOUBLE_EQ(norm.norm(u, 0.0), norm.norm(Vector::Zero(4), 1.0));
  BranchPoint from;
  from.u = Vector::Ones(4);
  from.lambda = 1.0;
  const Vector tu = Vector::Constant(4, 1.0);
  const Constraint c = norm.arclength(from, tu, 2.0, 0.3);
  EXPECT_NEAR(c.value(from.u + 0.1 * tu, from.lambda + 0.2), norm.dot(0.1 * tu, 0.2, tu, 2.0) - 0.3, 1e-15);
  EXPECT_DOUBLE_EQ(Constraint::parameter(0.7).value(from.u, 0.9), 0.9 - 0.7);
  EXPECT_THROW(ArclengthNorm(4, 0.0, 0.5), std::invalid_argument);
}
