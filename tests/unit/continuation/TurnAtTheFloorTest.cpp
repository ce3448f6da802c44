// Turns of a branch sharper than its smallest step: passed at the step floor, every point on the
// branch (StepController::judge_turn and after_turn, in Continuation::attempt and its trace loop).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "continuation/Continuation.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using namespace keller::test;

// lambda = -(5/8) u + (3/8) sqrt(u^2 + eps^2): slope -1 for u < 0, -1/4 for u > 0, the branch
// turning by 31 degrees within eps = 1e-13 of u = 0, far inside the smallest step (min_step 1e-8):
// more than the angle limit at any step. The steps are rejected for their turn down to the floor,
// where the turn is passed, the point being the step's own: the branch goes on and ends at its
// bound on the other side. (Before, the step fell below the floor and the branch ended there.)
TEST(Continuation, ATurnSharperThanTheSmallestStepIsPassedAtTheFloor) {
  const double eps = 1e-13;
  FunctionProblem problem(
      "kink", 1, {{"lambda", 0.9}},
      [eps](const Vector& u, const Vector& p) {
        return Vector::Constant(1, p[0] + 0.625 * u[0] - 0.375 * std::hypot(u[0], eps));
      },
      [eps](const Vector& u, const Vector&) {
        return Eigen::MatrixXd::Constant(1, 1, 0.625 - 0.375 * u[0] / std::hypot(u[0], eps));
      },
      [](int, const Vector&, const Vector&) { return Vector::Constant(1, 1.0); });
  ContinuationOptions o;
  o.parameter = "lambda";
  o.direction = -1;
  o.stop.lower = -0.2;
  o.state_scale = 1.0;
  o.step.initial = 0.05;
  o.step.max = 0.1;
  Continuation cont(problem, o);
  RecordingObserver rec;
  const auto r = cont.run(Vector::Constant(1, -0.9), rec);
  ASSERT_EQ(r.code, StopCode::LowerBound) << r.reason;
  EXPECT_NEAR(rec.points.back().u[0], 0.8, 1e-12);
  // every point on the branch; the turn passed once, at the floor
  for (const auto& q : rec.points) EXPECT_NEAR(q.lambda, -0.625 * q.u[0] + 0.375 * std::abs(q.u[0]), 1e-12);
  EXPECT_LT(rec.rejections.size(), 40u);
}

// A fold far sharper than the smallest step: lambda = sqrt(u^2 + eps^2), eps = 1e-13, the branch
// turning by 90 degrees at u = 0. It too is passed at the floor, onto the other arm (never to a
// point far away: the step at the floor may land anywhere the arclength row meets the branch), and
// every point lies on the branch.
TEST(Continuation, AFoldSharperThanTheSmallestStepIsPassedAtTheFloor) {
  const double eps = 1e-13;
  FunctionProblem problem(
      "corner", 1, {{"lambda", 0.9}},
      [eps](const Vector& u, const Vector& p) { return Vector::Constant(1, p[0] - std::hypot(u[0], eps)); },
      [eps](const Vector& u, const Vector&) { return Eigen::MatrixXd::Constant(1, 1, -u[0] / std::hypot(u[0], eps)); },
      [](int, const Vector&, const Vector&) { return Vector::Constant(1, 1.0); });
  ContinuationOptions o;
  o.parameter = "lambda";
  o.direction = -1;
  o.stop.upper = 0.95;
  o.state_scale = 1.0;
  o.step.initial = 0.05;
  o.step.max = 0.1;
  Continuation cont(problem, o);
  RecordingObserver rec;
  const auto r = cont.run(Vector::Constant(1, -0.9), rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  EXPECT_NEAR(rec.points.back().u[0], 0.95, 1e-12);
  for (const auto& q : rec.points) EXPECT_NEAR(q.lambda, std::abs(q.u[0]), 1e-12);
  // the fold is located where the parameter turns
  const auto folds = rec.of_kind(PointKind::Fold);
  ASSERT_EQ(folds.size(), 1u);
  EXPECT_NEAR(folds[0]->lambda, eps, o.events.tolerance);
  EXPECT_TRUE(rec.notes.empty());
}
