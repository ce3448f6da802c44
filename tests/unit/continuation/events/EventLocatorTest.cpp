// The event locator (continuation/events/EventLocator) on its own, on the cubic u^3 - 3u = lambda
// (CubicProblem): a requested value, a monitor's zero (by the secant and by Newton on the
// linearised function) and a fold, each located between two points of the branch to the event
// tolerance, against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

#include "support/ContinuationTestSupport.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using namespace keller::test;

namespace {

ContinuationOptions locator_options() {
  ContinuationOptions o;  // the defaults: the chord on a kept factorisation, block elimination
  o.parameter = "lambda";
  o.events.tolerance = 1e-10;
  return o;
}

// The point of the cubic at u, with its unit tangent (along decreasing u where `down`), its
// monitor (u - 1/2) and arclength s.
BranchPoint on_cubic(const ArclengthNorm& norm, double u, bool down, double s) {
  BranchPoint p;
  p.u = Vector::Constant(1, u);
  p.lambda = u * u * u - 3 * u;
  const double du = down ? -1.0 : 1.0, dl = du * (3 * u * u - 3), n = norm.norm(Vector::Constant(1, du), dl);
  p.tu = Vector::Constant(1, du / n);
  p.tlambda = dl / n;
  p.s = s;
  p.monitors = {u - 0.5};
  p.observables = {u};
  return p;
}

// The segment a -> b of the cubic between u = ua and u = ub (s: the chord's length).
std::pair<BranchPoint, BranchPoint> segment(const ArclengthNorm& norm, double ua, double ub) {
  const BranchPoint a = on_cubic(norm, ua, ub < ua, 0.0);
  return {a, on_cubic(norm, ub, ub < ua, norm.distance(a, on_cubic(norm, ub, ub < ua, 0.0)))};
}

// The root of u^3 - 3u = lambda on the middle branch (|u| < 1), |lambda| < 2: u = 2 cos(theta),
// cos(3 theta) = lambda / 2.
double middle_root(double lambda) { return 2 * std::cos((std::acos(lambda / 2) + 4 * M_PI) / 3); }

}  // namespace

// lambda = 0.7 between u = 0.5 and -0.5 (lambda -1.375 and 1.375): at exactly 0.7, u the root
// -0.23782 to the corrector's tolerance (|F| <= 1e-10, |dF/du| = 2.83 there), with its unit
// tangent oriented like a's (lambda increasing).
TEST(EventLocator, ARequestedValueExactly) {
  CubicProblem problem(0.0);
  EngineParts parts(problem, locator_options());
  const auto [a, b] = segment(parts.norm, 0.5, -0.5);
  std::string note;
  const std::optional<BranchPoint> p = parts.locator.locate_value(a, b, 0.7, note);
  ASSERT_TRUE(p) << note;
  EXPECT_EQ(p->lambda, 0.7);
  EXPECT_NEAR(p->u[0], middle_root(0.7), 1e-10 / 2.8);
  EXPECT_GT(p->s, a.s);
  EXPECT_LT(p->s, b.s);
  EXPECT_GT(p->tlambda, 0.0);
  EXPECT_NEAR(parts.norm.norm(p->tu, p->tlambda), 1.0, 1e-12);
  EXPECT_NEAR(p->tlambda / p->tu[0], 3 * p->u[0] * p->u[0] - 3, 1e-9);  // dlambda/du of the branch
}

// The monitor u - 1/2 between u = 0.7 and 0.3: its zero at u = 1/2, lambda = 1/8 - 3/2 = -1.375.
// By the secant, to the event tolerance in lambda (successive trials agree to it); by Newton on
// the monitor linearised with its gradient (1 in u), settled to 1e-2 of it, in fewer solves.
TEST(EventLocator, AMonitorsZeroBySecantAndByNewton) {
  CubicProblem problem(0.0);
  EngineParts parts(problem, locator_options());
  const auto [a, b] = segment(parts.norm, 0.7, 0.3);
  const Target monitor{EventTarget::Monitor, 0, 0.0};
  std::string note;
  const std::optional<BranchPoint> secant =
      parts.locator.locate_root(a, b, monitor, a.monitors[0], b.monitors[0], note);
  ASSERT_TRUE(secant) << note;
  EXPECT_NEAR(secant->lambda, -1.375, 1e-10);
  EXPECT_NEAR(secant->u[0], 0.5, 1e-10);
  const GradientFunction g = [](const Vector& u, double, double, bool gradient, double& value, Vector& gu, double& gl) {
    value = u[0] - 0.5;
    if (gradient) gu = Vector::Constant(1, 1.0), gl = 0.0;
    return Status{};
  };
  const std::optional<BranchPoint> newton = parts.locator.locate_by_newton(a, b, g, a.monitors[0], b.monitors[0], note);
  ASSERT_TRUE(newton) << note;
  EXPECT_NEAR(newton->lambda, -1.375, 1e-12);
  EXPECT_NEAR(newton->u[0], 0.5, 1e-12);
  std::cout << "lambda - (-1.375): secant " << secant->lambda + 1.375 << " in " << secant->iterations
            << " solves, Newton " << newton->lambda + 1.375 << " in " << newton->iterations << "\n";
  EXPECT_LT(newton->iterations, secant->iterations);
}

// The fold of the cubic at u = -1, lambda = 2, between u = -1.05 and -0.95 (where the tangent's
// parameter part changes sign; the tangents 33 degrees apart, a step's turn): lambda to the event
// tolerance; u, on which lambda depends quadratically there (lambda = 2 - 3 (u + 1)^2 + ...), to
// about its square root.
TEST(EventLocator, AFold) {
  CubicProblem problem(0.0);
  EngineParts parts(problem, locator_options());
  const auto [a, b] = segment(parts.norm, -1.05, -0.95);
  ASSERT_LT(a.tlambda * b.tlambda, 0.0);
  std::string note;
  const std::optional<BranchPoint> p =
      parts.locator.locate_root(a, b, Target{EventTarget::Fold, -1, 0.0}, a.tlambda, b.tlambda, note);
  ASSERT_TRUE(p) << note;
  EXPECT_NEAR(p->lambda, 2.0, 1e-10);
  EXPECT_NEAR(p->u[0], -1.0, 1e-5);
  EXPECT_LT(std::abs(p->tlambda), 1e-4);
  std::cout << "fold: lambda - 2 = " << p->lambda - 2 << ", u + 1 = " << p->u[0] + 1 << ", t_lambda " << p->tlambda
            << "\n";
}

// A monitor with a pole, 1 / (u - 1/2), changes sign between u = 0.7 and 0.3 without a zero (as the
// minimally augmented test function 1 / (c^T J^-1 b) does when c^T J^-1 b passes through zero):
// the locator narrows the bracket onto u = 1/2, sees |g| grow past the ends' values, and reports no
// point, saying why; the same segment with the monitor u - 1/2 has its zero located, and so has a
// segment that starts 1e-14 from it.
TEST(EventLocator, APoleOfAMonitorIsNoZero) {
  FunctionProblem problem(
      "cubic with a pole", 1, {{"lambda", 0.0}},
      [](const Vector& u, const Vector& p) { return Vector::Constant(1, u[0] * u[0] * u[0] - 3 * u[0] - p[0]); },
      [](const Vector& u, const Vector&) { return Eigen::MatrixXd::Constant(1, 1, 3 * u[0] * u[0] - 3); },
      [](int, const Vector&, const Vector&) { return Vector::Constant(1, -1.0); });
  problem.set_monitors({"pole", "zero"}, [](const Vector& u) {
    return std::vector<double>{1.0 / (u[0] - 0.5), u[0] - 0.5};
  });
  EngineParts parts(problem, locator_options());
  auto [a, b] = segment(parts.norm, 0.7, 0.3);
  a.monitors = {1.0 / (0.7 - 0.5), 0.7 - 0.5};
  b.monitors = {1.0 / (0.3 - 0.5), 0.3 - 0.5};
  std::string note;
  EXPECT_FALSE(
      parts.locator.locate_root(a, b, Target{EventTarget::Monitor, 0, 0.0}, a.monitors[0], b.monitors[0], note));
  EXPECT_NE(note.find("pole"), std::string::npos) << note;
  note.clear();
  const std::optional<BranchPoint> zero =
      parts.locator.locate_root(a, b, Target{EventTarget::Monitor, 1, 0.0}, a.monitors[1], b.monitors[1], note);
  ASSERT_TRUE(zero) << note;
  EXPECT_NEAR(zero->u[0], 0.5, 1e-10);
  // a zero next to an end whose value is rounding (a restart from a located event) is a zero
  note.clear();
  auto [c, d] = segment(parts.norm, 0.5 + 1e-14, 0.3);
  c.monitors = {1.0 / 1e-14, 1e-14};
  d.monitors = {1.0 / (0.3 - 0.5), 0.3 - 0.5};
  const std::optional<BranchPoint> near =
      parts.locator.locate_root(c, d, Target{EventTarget::Monitor, 1, 0.0}, c.monitors[1], d.monitors[1], note);
  ASSERT_TRUE(near) << note;
  EXPECT_NEAR(near->u[0], 0.5, 1e-10);
}

// A partial monitor (continuation/engine/AugmentedProblem.hpp) that changes sign between u = 0.7
// and 0.3 but is undefined (NaN) for |u - 1/2| < 0.1, as a Hopf curve's l1 is where omega nears 0:
// no zero is sought inside the undefined band, and no point is reported (a bisection onto the
// band's edge would report a false one); the same monitor defined everywhere has its zero located.
TEST(EventLocator, AMonitorUndefinedInsideTheStepHasNoZero) {
  FunctionProblem problem(
      "cubic with an undefined band", 1, {{"lambda", 0.0}},
      [](const Vector& u, const Vector& p) { return Vector::Constant(1, u[0] * u[0] * u[0] - 3 * u[0] - p[0]); },
      [](const Vector& u, const Vector&) { return Eigen::MatrixXd::Constant(1, 1, 3 * u[0] * u[0] - 3); },
      [](int, const Vector&, const Vector&) { return Vector::Constant(1, -1.0); });
  problem.set_monitors({"partial", "whole"}, [](const Vector& u) {
    return std::vector<double>{std::abs(u[0] - 0.5) < 0.1 ? NAN : u[0] - 0.5, u[0] - 0.5};
  });
  EngineParts parts(problem, locator_options());
  auto [a, b] = segment(parts.norm, 0.7, 0.3);
  a.monitors = {0.2, 0.2};
  b.monitors = {-0.2, -0.2};
  std::string note;
  EXPECT_FALSE(
      parts.locator.locate_root(a, b, Target{EventTarget::Monitor, 0, 0.0}, a.monitors[0], b.monitors[0], note));
  EXPECT_NE(note.find("undefined"), std::string::npos) << note;
  note.clear();
  const std::optional<BranchPoint> zero =
      parts.locator.locate_root(a, b, Target{EventTarget::Monitor, 1, 0.0}, a.monitors[1], b.monitors[1], note);
  ASSERT_TRUE(zero) << note;
  EXPECT_NEAR(zero->u[0], 0.5, 1e-10);
}
