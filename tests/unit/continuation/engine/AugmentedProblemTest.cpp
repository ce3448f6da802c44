// Where the engine finds a problem's border (continuation/engine/AugmentedProblem.hpp): an ordinary
// problem has none (its own pattern, no turning unknowns); the curves are augmented problems, with
// the border each eliminates, the pattern of the matrix factorised and p1 as a turning unknown.
#include <gtest/gtest.h>

#include "continuation/curves/EventCurveProblem.hpp"
#include "continuation/curves/FoldCurveProblem.hpp"
#include "continuation/engine/AugmentedProblem.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

// F = (u0^2 - a, u1 - b u0): two unknowns, two parameters, a monitor "u1".
test::FunctionProblem two_by_two() {
  test::FunctionProblem p(
      "two", 2, {{"a", 1.0}, {"b", 0.5}},
      [](const Vector& u, const Vector& q) { return Eigen::Vector2d(u[0] * u[0] - q[0], u[1] - q[1] * u[0]); },
      [](const Vector& u, const Vector& q) {
        Eigen::MatrixXd J(2, 2);
        J << 2 * u[0], 0, -q[1], 1;
        return J;
      },
      [](int k, const Vector& u, const Vector&) {
        return k == 0 ? Eigen::Vector2d(-1, 0) : Eigen::Vector2d(0, -u[0]);
      });
  p.set_monitors({"u1"}, [](const Vector& u) { return std::vector<double>{u[1]}; });
  return p;
}

}  // namespace

TEST(AugmentedProblem, AnOrdinaryProblemHasNoBorder) {
  test::CubicProblem p(0.0);
  EXPECT_EQ(augmented(p), nullptr);
  EXPECT_EQ(border_size(p), 0);
  EXPECT_EQ(&inner_pattern(p), &p.jacobian_pattern());
  EXPECT_TRUE(turning_unknowns(p).empty());
  EXPECT_FALSE(Evaluator(p, 0, "lambda").bordered());
}

// A fold curve's inner J is singular all along it: no border, the whole augmented pattern
// (3 x 3 for two unknowns and p1) factorised.
TEST(AugmentedProblem, AFoldCurveIsFactorisedWhole) {
  test::FunctionProblem p = two_by_two();
  FoldCurveProblem curve(p, "a");
  const AugmentedProblem* a = augmented(curve);
  ASSERT_EQ(a, &curve);
  EXPECT_EQ(border_size(curve), 0);
  EXPECT_EQ(&inner_pattern(curve), &curve.jacobian_pattern());
  EXPECT_EQ(inner_pattern(curve).rows(), 3);
  const auto turning = turning_unknowns(curve);
  ASSERT_EQ(turning.size(), 1u);
  EXPECT_EQ(turning[0].index, 2);
  EXPECT_EQ(turning[0].name, "a");
  EXPECT_FALSE(Evaluator(curve, p.parameters().index("b"), "b").bordered());
}

// An event curve borders the inner J by one row and column: the inner pattern is the inner
// problem's, and its Jacobian comes in bordered form.
TEST(AugmentedProblem, AnEventCurveBordersTheInnerJacobianByOne) {
  test::FunctionProblem p = two_by_two();
  EventCurveProblem curve(p, "a", "u1");
  EXPECT_EQ(augmented(curve), &curve);
  EXPECT_EQ(border_size(curve), 1);
  EXPECT_EQ(&inner_pattern(curve), &p.jacobian_pattern());
  const auto turning = turning_unknowns(curve);
  ASSERT_EQ(turning.size(), 1u);
  EXPECT_EQ(turning[0].index, 2);
  EXPECT_EQ(turning[0].name, "a");
  Evaluator ev(curve, p.parameters().index("b"), "b");
  EXPECT_TRUE(ev.bordered());
  const Vector U = curve.state(Eigen::Vector2d(1.0, 0.5), 1.0);
  ASSERT_TRUE(ev.jacobian(U).is_ok());
  EXPECT_EQ(ev.bordered_jacobian().border_size(), 1);
  EXPECT_EQ(ev.jacobian_matrix().rows(), 3);
}
