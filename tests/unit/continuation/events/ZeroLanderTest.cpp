// The lander (continuation/events/ZeroLander) on its own: a step that lands on the stop
// observable's threshold, planned from the function and its gradient at the step's start,
// predicted under the function linearised there, corrected, and settled by Newton on the function
// itself, against the closed form of a branch u_i = exp(c_i lambda).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/MonitorGradients.hpp"
#include "support/ContinuationTestSupport.hpp"

using namespace keller;
using namespace keller::test;

namespace {

// F_i = u_i - exp(c_i lambda); observable u0^2 with its gradient (2 u0, 0): on the branch it is
// exp(2 c_0 lambda), equal to K at lambda = ln K / (2 c_0).
class SquaredExponential final : public DiagonalProblem, public MonitorGradients {
 public:
  SquaredExponential() : DiagonalProblem("squared-exponential", 2, 0.0) {}
  static constexpr double c[2] = {0.7, -0.4};
  static BranchPoint at(const ArclengthNorm& norm, double lambda, double K) {
    BranchPoint p;
    p.lambda = lambda;
    p.u = Vector{{std::exp(c[0] * lambda), std::exp(c[1] * lambda)}};
    const Vector du{{c[0] * p.u[0], c[1] * p.u[1]}};
    const double n = norm.norm(du, 1.0);
    p.tu = du / n;
    p.tlambda = 1.0 / n;
    p.observables = {p.u[0] * p.u[0]};
    p.monitors = {p.observables[0] - K};  // the threshold's monitor
    return p;
  }
  Vector initial_guess() override { return Vector::Ones(2); }
  std::vector<std::string> observable_names() const override { return {"u0^2"}; }
  Status observables(const Vector& u, std::vector<double>& v) override {
    v = {u[0] * u[0]};
    return {};
  }
  bool has_observable_gradient(int) const override { return true; }
  Status observable_gradient(int, const Vector& u, Vector& g) override {
    g = Vector{{2 * u[0], 0.0}};
    return {};
  }

 private:
  double f(int i, double u, double l) const override { return u - std::exp(c[i] * l); }
  double df_du(int, double, double) const override { return 1.0; }
  double df_dlambda(int i, double, double l) const override { return -c[i] * std::exp(c[i] * l); }
};

ContinuationOptions landing_options(double K) {
  ContinuationOptions o;
  o.parameter = "lambda";
  o.stop.observable = "u0^2";
  o.stop.above = K;
  o.step.max = 1.0;
  return o;
}

}  // namespace

// From lambda = 0.5 with a step of 0.55, the threshold u0^2 = 4 (lambda* = ln 4 / 1.4 = 0.990):
// the plan lands at the linear prediction's zero, -g / (g' ds) of the step; the prediction's row is
// g linearised at the start; the corrected point lies where that linearisation vanishes, not on
// the threshold (u0^2 is not linear); Newton on g itself settles it to 1e-2 of the event
// tolerance in lambda.
TEST(ZeroLander, AStepLandsOnTheThreshold) {
  const double K = 4.0, lambda_star = std::log(K) / (2 * SquaredExponential::c[0]);
  SquaredExponential problem;
  EngineParts parts(problem, landing_options(K));
  parts.lander.configure(0, 0, {"u0^2 > stop_above"});
  EXPECT_EQ(parts.lander.observable_of(0), 0);
  ASSERT_TRUE(parts.lander.gradient_of(0));
  const BranchPoint cur = SquaredExponential::at(parts.norm, 0.5, K);
  const double ds = 0.55, g = cur.monitors[0], slope = 2 * cur.u[0] * cur.tu[0];
  const std::optional<ZeroLanding> z = parts.lander.plan(cur, cur.tu, cur.tlambda, ds);
  ASSERT_TRUE(z);
  EXPECT_NEAR(z->land.fraction, -g / (slope * ds), 1e-6);  // (the gradient in lambda by differences: 0)
  EXPECT_GT(z->land.fraction, 1.0);                        // beyond the planned step, within 1.25 of it
  EXPECT_EQ(z->land.end, StopCode::StopObservable);
  EXPECT_EQ(z->land.label, "u0^2 > stop_above");
  EXPECT_EQ(z->land.monitor, 0);

  Prediction pr;
  ZeroLander::predict(*z, cur, cur.tu, cur.tlambda, ds, pr);
  EXPECT_NEAR(pr.lambda, cur.lambda + z->land.fraction * ds * cur.tlambda, 1e-15);
  EXPECT_NEAR(pr.constraint.value(pr.u, pr.lambda), 0.0, 1e-6);  // on the linearised zero
  BranchPoint nxt;
  nxt.u = pr.u;
  nxt.lambda = pr.lambda;
  const CorrectorResult r = parts.corrector.correct(nxt.u, nxt.lambda, pr.constraint, Corrector::Kind::Step);
  ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
  const double off = nxt.u[0] * nxt.u[0] - K;
  EXPECT_GT(std::abs(off), 1e-3);  // the linearisation's zero is not the threshold

  const ZeroLander::Settled settled = parts.lander.settle(*z, cur, nxt, 0.0);
  ASSERT_TRUE(settled.settled);
  EXPECT_GE(settled.solves, 1);
  EXPECT_LE(settled.residual, 1e-10);
  EXPECT_NEAR(nxt.lambda, lambda_star, 1e-2 * parts.options.events.tolerance);
  EXPECT_NEAR(nxt.u[0], 2.0, 1e-9);
  EXPECT_NEAR(nxt.u[1], std::exp(SquaredExponential::c[1] * nxt.lambda), 1e-10);
}

// No landing where the threshold lies more than 1.25 steps ahead, where the step moves away from
// it, or where landing on zeros is off.
TEST(ZeroLander, NoLandingOutOfReach) {
  const double K = 4.0;
  SquaredExponential problem;
  EngineParts parts(problem, landing_options(K));
  parts.lander.configure(0, 0, {"u0^2 > stop_above"});
  const BranchPoint cur = SquaredExponential::at(parts.norm, 0.5, K);
  EXPECT_TRUE(parts.lander.plan(cur, cur.tu, cur.tlambda, 0.55));   // 1.13 steps ahead
  EXPECT_FALSE(parts.lander.plan(cur, cur.tu, cur.tlambda, 0.45));  // 1.38 steps ahead
  EXPECT_FALSE(parts.lander.plan(cur, -cur.tu, -cur.tlambda, 0.55));
  ContinuationOptions off = landing_options(K);
  off.events.land_on_zeros = false;
  EngineParts without(problem, off);
  without.lander.configure(0, 0, {"u0^2 > stop_above"});
  EXPECT_FALSE(without.lander.plan(cur, cur.tu, cur.tlambda, 0.55));
}
