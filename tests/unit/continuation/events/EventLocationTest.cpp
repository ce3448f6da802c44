// Zeros of monitors and stop observables whose gradient the problem offers, located by Newton on
// F = 0 with the function linearised (MonitorGradients::has_monitor_gradient, has_observable_gradient),
// against closed forms and against the secant trials used without a gradient; and a start solved
// only to near the tolerance, finished on the factorisation it is given.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "continuation/Continuation.hpp"
#include "core/MonitorGradients.hpp"
#include "support/ContinuationTestSupport.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using namespace keller::test;

namespace {

// u_i = exp(c_i lambda): F_i = u_i - exp(c_i lambda). Monitor and observable "u0 u1" - K, a
// nonlinear function of the state that is exp((c_0 + c_1) lambda) - K on the branch: zero at
// lambda = ln K / (c_0 + c_1).
class ExponentialBranch final : public DiagonalProblem, public MonitorGradients {
 public:
  enum class Gradient { None, Exact, Zero };
  ExponentialBranch(double K, Gradient g) : DiagonalProblem("exponential", 4, 0.0), K_(K), gradient_(g) {}
  static constexpr double c[4] = {0.7, 0.5, -0.3, 1.1};
  static double zero_of(double K) { return std::log(K) / (c[0] + c[1]); }
  Vector initial_guess() override { return Vector::Ones(4); }
  std::vector<std::string> observable_names() const override { return {"u0 u1"}; }
  Status observables(const Vector& u, std::vector<double>& v) override {
    v = {u[0] * u[1]};
    return {};
  }
  std::vector<std::string> monitor_names() const override { return {"u0 u1 - K"}; }
  Status monitors(const Vector& u, std::vector<double>& v) override {
    v = {u[0] * u[1] - K_};
    return {};
  }
  bool has_monitor_gradient(int) const override { return gradient_ != Gradient::None; }
  Status monitor_gradient(int, const Vector& u, Vector& g) override { return product_gradient(u, g); }
  bool has_observable_gradient(int) const override { return gradient_ != Gradient::None; }
  Status observable_gradient(int, const Vector& u, Vector& g) override { return product_gradient(u, g); }

 private:
  Status product_gradient(const Vector& u, Vector& g) const {
    g = Vector::Zero(4);
    if (gradient_ == Gradient::Exact) g[0] = u[1], g[1] = u[0];
    return {};
  }
  double f(int i, double u, double l) const override { return u - std::exp(c[i] * l); }
  double df_du(int, double, double) const override { return 1.0; }
  double df_dlambda(int i, double, double l) const override { return -c[i] * std::exp(c[i] * l); }
  double K_;
  Gradient gradient_;
};

ContinuationOptions exponential_options() {
  ContinuationOptions o;  // the defaults: the chord on a kept factorisation, block elimination
  o.parameter = "lambda";
  o.stop.lower = -1.0;
  o.stop.upper = 2.0;
  o.step.initial = 0.1;
  o.step.max = 0.4;
  o.events.tolerance = 1e-10;
  return o;
}

struct Located {
  BranchPoint event;
  BranchPoint end;
};

Located trace(ExponentialBranch::Gradient g, const ContinuationOptions& o) {
  ExponentialBranch problem(std::exp(1.2 * 0.9), g);  // the monitor's zero at lambda = 0.9
  Continuation cont(problem, o);
  RecordingObserver rec;
  const ContinuationResult r = cont.run(problem.initial_guess(), rec);
  EXPECT_EQ(r.code, o.stop.observable.empty() ? StopCode::UpperBound : StopCode::StopObservable) << r.reason;
  Located out;
  const auto events = rec.of_kind(PointKind::Event);
  EXPECT_EQ(events.size(), 1u);
  if (!events.empty()) out.event = *events[0];
  if (!rec.points.empty()) out.end = rec.points.back();
  return out;
}

// Three steps of the branch of problem: the factorisation the run hands on, and its last point.
struct ShortRun {
  StartFactorisation factorisation;
  BranchPoint last;
};
ShortRun three_steps(ExponentialBranch& problem) {
  ContinuationOptions o = exponential_options();
  o.stop.max_steps = 3;
  Continuation run(problem, o);
  RecordingObserver rec;
  run.run(problem.initial_guess(), rec);
  return {run.factorisation(), rec.points.back()};
}

}  // namespace

// The monitor's zero to the event tolerance with and without its gradient; with it, in fewer
// corrector solves than the secant's trials (each of which is corrected onto the branch).
TEST(EventLocation, AMonitorWithAGradientIsLocatedByNewtonInFewerSolves) {
  const ContinuationOptions o = exponential_options();
  const double exact = ExponentialBranch::zero_of(std::exp(1.2 * 0.9));
  const Located newton = trace(ExponentialBranch::Gradient::Exact, o);
  const Located secant = trace(ExponentialBranch::Gradient::None, o);
  std::cout << "the zero at lambda = " << exact << ": Newton " << newton.event.lambda << " in "
            << newton.event.iterations << " solves, secant " << secant.event.lambda << " in " << secant.event.iterations
            << "\n";
  EXPECT_NEAR(newton.event.lambda, exact, o.events.tolerance);
  EXPECT_NEAR(secant.event.lambda, exact, o.events.tolerance);
  // the located state is on the branch (the corrector's tolerance) and at the zero
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(newton.event.u[i], std::exp(ExponentialBranch::c[i] * newton.event.lambda), 1e-9);
  EXPECT_NEAR(newton.event.monitors[0], 0.0, 1e-9);
  EXPECT_LT(newton.event.iterations, secant.event.iterations);
  // a unit tangent at the located point, along the branch: (u', 1) / |.| with u_i' = c_i u_i
  EXPECT_GT(newton.event.tlambda, 0.0);
  EXPECT_NEAR(newton.event.tu[0] / newton.event.tlambda, ExponentialBranch::c[0] * newton.event.u[0], 1e-6);
}

// A stop observable with a gradient: the branch ends on its threshold, located by Newton (the
// step that crosses it not landing on it).
TEST(EventLocation, AStopObservableWithAGradientEndsTheBranchOnItsThreshold) {
  ContinuationOptions o = exponential_options();
  o.stop.observable = "u0 u1";
  o.stop.above = std::exp(1.2 * 1.4);  // reached at lambda = 1.4
  o.events.land_on_zeros = false;
  const Located newton = trace(ExponentialBranch::Gradient::Exact, o);
  const Located secant = trace(ExponentialBranch::Gradient::None, o);
  EXPECT_EQ(newton.end.kind, PointKind::End);
  EXPECT_NEAR(newton.end.lambda, 1.4, o.events.tolerance);
  EXPECT_NEAR(secant.end.lambda, 1.4, o.events.tolerance);
  EXPECT_NEAR(newton.end.observables[0], o.stop.above, 1e-9);
  EXPECT_LT(newton.end.iterations, secant.end.iterations);
}

// A gradient that is useless (zero: the function seems not to change along the branch) is
// caught and the secant locates the zero instead: the same point, not a failure.
TEST(EventLocation, WhereNewtonCannotLocateTheSecantDoes) {
  const ContinuationOptions o = exponential_options();
  const Located fallback = trace(ExponentialBranch::Gradient::Zero, o);
  const Located secant = trace(ExponentialBranch::Gradient::None, o);
  EXPECT_NEAR(fallback.event.lambda, ExponentialBranch::zero_of(std::exp(1.2 * 0.9)), o.events.tolerance);
  EXPECT_NEAR(fallback.event.lambda, secant.event.lambda, 1e-12);
}

// A run given a factorisation and a start that solves F only to about 1e-6 (a switch of an event
// curve starts its next piece so): the start is corrected on that factorisation before the first
// step, and is reported at the tolerance; without a correction its residual would stay 1e-6.
TEST(EventLocation, AStartNearTheToleranceIsFinishedOnTheGivenFactorisation) {
  ContinuationOptions o = exponential_options();
  o.stop.max_steps = 3;
  ExponentialBranch problem(10.0, ExponentialBranch::Gradient::Exact);
  const ShortRun first = three_steps(problem);
  const StartFactorisation& f = first.factorisation;
  ASSERT_TRUE(f.lu);
  const BranchPoint& last = first.last;
  problem.parameters().set("lambda", last.lambda);
  Vector start = last.u;
  start[2] += 1e-6;  // F_2 = 1e-6 there
  Continuation second(problem, o);
  RecordingObserver rec2;
  const ContinuationResult r = second.run(start, rec2, f);
  ASSERT_GE(rec2.points.size(), 2u) << r.reason;
  const BranchPoint& s = rec2.points.front();
  EXPECT_EQ(s.kind, PointKind::Start);
  EXPECT_EQ(s.lambda, last.lambda);  // at the same parameter value
  EXPECT_LE(s.residual, 1e-10);
  EXPECT_NEAR(s.u[2], std::exp(ExponentialBranch::c[2] * last.lambda), 1e-10);
}

// A step predicted to cross the stop observable's threshold lands on it: its row is the
// function linearised at the step's start (u0 u1 is exp(1.2 lambda) on the branch: the linear
// prediction falls short, and Newton settles the zero). The end is the step's own row, at the
// threshold to the event tolerance, in fewer corrector solves than a step past it and its location.
TEST(EventLocation, AStepLandsOnTheStopObservablesThreshold) {
  ContinuationOptions o = exponential_options();
  o.stop.observable = "u0 u1";
  o.stop.above = std::exp(1.2 * 1.4);  // reached at lambda = 1.4
  long solves[2] = {0, 0};
  for (const bool land : {true, false}) {
    o.events.land_on_zeros = land;
    ExponentialBranch problem(std::exp(1.2 * 0.9), ExponentialBranch::Gradient::Exact);
    Continuation cont(problem, o);
    RecordingObserver rec;
    const ContinuationResult r = cont.run(problem.initial_guess(), rec);
    ASSERT_EQ(r.code, StopCode::StopObservable) << r.reason;
    const BranchPoint& end = rec.points.back();
    EXPECT_EQ(end.kind, PointKind::End);
    EXPECT_NEAR(end.lambda, 1.4, o.events.tolerance) << land;
    EXPECT_NEAR(end.observables[0], o.stop.above, 1e-9) << land;
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(end.u[i], std::exp(ExponentialBranch::c[i] * end.lambda), 1e-9);
    // the landed end is the step's row: it reports the step's corrector iterations
    if (land) {
      EXPECT_GT(end.iterations, 0);
    }
    solves[land ? 0 : 1] = r.timings.solves;
  }
  std::cout << "corrector and tangent solves: landing " << solves[0] << ", a step past the threshold and its location "
            << solves[1] << "\n";
  EXPECT_LT(solves[0], solves[1]);
}

// The renewal cost a run measured goes with the factorisation it hands on: a run (an event
// curve's next piece) that adopts it uses that cost until it has measured its own, instead of
// renewing at its first slow chord as if a renewal cost nothing.
TEST(EventLocation, AnAdoptedFactorisationBringsItsRenewalCost) {
  ExponentialBranch problem(10.0, ExponentialBranch::Gradient::Exact);
  const ShortRun first = three_steps(problem);
  StartFactorisation f = first.factorisation;
  ASSERT_TRUE(f.lu);
  EXPECT_GT(f.renewal_cost, 0.0);
  f.renewal_cost = 17.0;
  const BranchPoint& last = first.last;
  Evaluator ev(problem, problem.parameters().index("lambda"), "lambda");
  KeptFactorisation kept(problem, {}, true);
  EXPECT_EQ(kept.measured_renewal_cost(ev.timings()), 0.0);  // nothing measured, nothing adopted
  ASSERT_TRUE(kept.adopt_at(ev, f, last.u, last.lambda, Constraint::parameter(last.lambda)).is_ok());
  EXPECT_EQ(kept.measured_renewal_cost(ev.timings()), 17.0);
}
