// The parts of the continuation engine, each on synthetic inputs: the renewal policy from given
// residual histories, the convergence test from given iterates, the step controller from a
// sequence of outcomes, the landing plan from given stops and a predicted step, the crossings of a
// segment and the order of located points, bracketing by bisection, the branch-point monitor from
// given determinant signs, the spectrum scheduler from given counts, and the arclength norm.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/Predictor.hpp"
#include "continuation/engine/StepController.hpp"
#include "continuation/engine/TangentSolver.hpp"
#include "continuation/events/Bracket.hpp"
#include "continuation/events/BranchPointMonitor.hpp"
#include "continuation/events/EventDetector.hpp"
#include "continuation/events/SpectrumScheduler.hpp"
#include "core/ConvergenceTest.hpp"
#include "core/RenewalPolicy.hpp"

using namespace keller;

namespace {

RenewalPolicy::History history(int k, int on_matrix, double residual, double previous, double before, double goal) {
  RenewalPolicy::History h;
  h.iteration = k;
  h.on_this_matrix = on_matrix;
  h.residual = residual;
  h.previous = previous;
  h.before_previous = before;
  h.goal = goal;
  return h;
}

}  // namespace

// The rate rule: keep the factorisation while |F| falls by at least chord_rate per iteration.
TEST(RenewalPolicy, TheRateRuleKeepsAFastChord) {
  RenewalPolicy p;  // chord_rate 0.25, no cost
  p.max_iterations = 30;
  EXPECT_FALSE(p.renew(history(1, 1, 2e-3, 1e-2, INFINITY, 1e-10)));  // fell by 0.2
  EXPECT_TRUE(p.renew(history(1, 1, 3e-3, 1e-2, INFINITY, 1e-10)));   // by 0.3
  RenewalPolicy::History damped = history(1, 1, 1e-3, 1e-2, INFINITY, 1e-10);
  damped.full_step = false;  // a line search damped it: the matrix no longer points the way
  EXPECT_TRUE(p.renew(damped));
  p.chord_rate = 0.0;  // never keep
  EXPECT_TRUE(p.renew(history(1, 1, 1e-6, 1e-2, INFINITY, 1e-10)));
}

// At its observed rate (the mean of its last two on this matrix) a chord at 1e-6 falling by 0.5 per
// iteration needs log(1e-10 / 1e-6) / log(0.5) = 13.3 more iterations to reach 1e-10.
TEST(RenewalPolicy, ItsRateSaysHowManyMoreIterations) {
  EXPECT_NEAR(RenewalPolicy::iterations_to_goal(history(3, 1, 1e-6, 2e-6, INFINITY, 1e-10)), 13.29, 0.01);
  // two iterations on this matrix: the rate is the geometric mean of the two ratios (0.5 and 0.8)
  EXPECT_NEAR(RenewalPolicy::iterations_to_goal(history(3, 2, 1e-6, 1.25e-6, 2.5e-6, 1e-10)),
              std::log(1e-4) / std::log(std::sqrt(0.4)), 1e-9);
  EXPECT_TRUE(std::isinf(RenewalPolicy::iterations_to_goal(history(3, 1, 1e-6, 1e-6, INFINITY, 1e-10))));
  EXPECT_EQ(RenewalPolicy::iterations_to_goal(history(3, 1, 1e-11, 2e-11, INFINITY, 1e-10)), 0.0);
}

// renewal_cost: a chord slower than the rate goes on where it needs at most that many more
// iterations and still reaches its goal two before the limit.
TEST(RenewalPolicy, ACostedChordGoesOnWhileCheaperThanARenewal) {
  RenewalPolicy p;
  p.max_iterations = 30;
  p.renewal_cost = 25;
  const auto slow = history(3, 1, 1e-6, 2e-6, INFINITY, 1e-10);  // 13.3 more at 0.5
  EXPECT_FALSE(p.renew(slow));
  p.renewal_cost = 10;  // a renewal costs less than those 13 solves
  EXPECT_TRUE(p.renew(slow));
  p.renewal_cost = 25;
  EXPECT_TRUE(p.renew(history(16, 1, 1e-6, 2e-6, INFINITY, 1e-10)));   // 16 + 13.3 > 30 - 2
  EXPECT_TRUE(p.renew(history(3, 1, 1e-6, 0.9e-6, INFINITY, 1e-10)));  // growing: never
}

// A located point on a kept factorisation keeps it while the chord reaches its goal before the
// limit, whatever its rate (a few more solves are cheaper than a factorisation).
TEST(RenewalPolicy, ALocatedChordKeepsWhileItReachesItsGoal) {
  RenewalPolicy p;
  p.max_iterations = 30;
  p.reach_goal = true;
  EXPECT_FALSE(p.renew(history(2, 1, 1e-6, 2e-6, INFINITY, 1e-10)));    // 2 + 13.3 <= 28
  EXPECT_TRUE(p.renew(history(15, 1, 1e-6, 2e-6, INFINITY, 1e-10)));    // 15 + 13.3 > 28
  EXPECT_FALSE(p.renew(history(2, 1, 1e-6, 1.6e-6, INFINITY, 1e-10)));  // 0.63 per iteration: 20 more
}

// Near the rounding floor a slower fall is rounding, not an old matrix.
TEST(RenewalPolicy, BelowTheFloorLevelASlowFallKeepsTheMatrix) {
  RenewalPolicy p;
  p.max_iterations = 10;
  p.floor_level = 1e-12;
  EXPECT_FALSE(p.renew(history(4, 1, 8e-13, 1e-12, INFINITY, 1e-15)));
  EXPECT_TRUE(p.renew(history(4, 1, 8e-11, 1e-10, INFINITY, 1e-15)));
}

namespace {

ConvergenceTest::Iterate iterate(double residual, double previous, double before = INFINITY, double update = INFINITY,
                                 double contraction = 0.0) {
  ConvergenceTest::Iterate it;
  it.residual = residual;
  it.previous = previous;
  it.before_previous = before;
  it.update = update;
  it.contraction = contraction;
  return it;
}

}  // namespace

TEST(ConvergenceTest, AtTheToleranceOrAtARaisedGoal) {
  ConvergenceTest t;
  t.tolerance = 1e-10;
  t.update_tolerance = 1e-12;
  EXPECT_EQ(t.judge(iterate(9e-11, 1e-6)), ConvergenceTest::Verdict::Converged);
  EXPECT_EQ(t.judge(iterate(2e-10, 1e-6)), ConvergenceTest::Verdict::Continue);
  t.goal = 5e-10;  // the floor neighbouring points reached
  EXPECT_EQ(t.judge(iterate(2e-10, 1e-6)), ConvergenceTest::Verdict::Converged);
}

// The goal of a chord allowed to stop at rounding: the neighbours' floor, but never below the
// problem's own floor (neighbours that landed on an exact zero by luck, as a linear problem's
// may, would otherwise ask the chord for the tolerance, below rounding) nor above the floor level.
TEST(ConvergenceTest, AChordAimsAtTheNeighboursFloorBetweenTheProblemsFloorAndTheFloorLevel) {
  ConvergenceTest t;
  t.tolerance = 1e-14;
  t.problem_floor = 3e-12;
  t.aim_at_floor(4.4e-12);
  EXPECT_DOUBLE_EQ(t.aim(), 4.4e-12);
  t.aim_at_floor(0.0);  // both neighbours at an exact zero
  EXPECT_DOUBLE_EQ(t.aim(), 3e-12);
  t.aim_at_floor(1.0);  // a neighbour far above the floor level (1e3 tol = 1e-11)
  EXPECT_DOUBLE_EQ(t.aim(), 1e-11);
  t.problem_floor = 0.0;
  t.aim_at_floor(0.0);  // nothing known: the tolerance
  EXPECT_DOUBLE_EQ(t.aim(), 1e-14);
}

// A residual that stops falling (by less than half) is the rounding floor only within the floor
// level: 1e3 times the tolerance, or the problem's own floor where that is higher (1D Bratu on
// 20000 intervals stalls at 1.4e-7, eps |J| |u| = 3.6e-7, against a tolerance of 1e-10).
TEST(ConvergenceTest, AStallIsTheFloorOnlyBelowTheFloorLevel) {
  ConvergenceTest t;
  t.tolerance = 1e-10;
  t.update_tolerance = 1e-12;
  EXPECT_EQ(t.judge(iterate(8e-8, 1e-7)), ConvergenceTest::Verdict::RoundingFloor);  // within 1e3 tol
  EXPECT_EQ(t.judge(iterate(1.4e-7, 1.6e-7)), ConvergenceTest::Verdict::Continue);   // above it
  t.problem_floor = 3.6e-7;
  EXPECT_DOUBLE_EQ(t.floor_level(), 3.6e-7);
  EXPECT_EQ(t.judge(iterate(1.4e-7, 1.6e-7)), ConvergenceTest::Verdict::RoundingFloor);
  EXPECT_EQ(t.judge(iterate(1.4e-7, 1.0e-6)), ConvergenceTest::Verdict::Continue);  // still falling
}

// A chord allowed to fall slowly has stopped only when two iterations together cut |F| by less
// than 10%: a steady 0.6 per iteration is not rounding.
TEST(ConvergenceTest, ASlowChordMustStallOverTwoIterations) {
  ConvergenceTest t;
  t.tolerance = 1e-10;
  t.slow = true;
  EXPECT_EQ(t.judge(iterate(3.6e-8, 6e-8, 1e-7)), ConvergenceTest::Verdict::Continue);
  EXPECT_EQ(t.judge(iterate(9.5e-8, 9.8e-8, 1e-7)), ConvergenceTest::Verdict::RoundingFloor);
  t.slow = false;
  EXPECT_EQ(t.judge(iterate(3.6e-8, 6e-8, 1e-7)), ConvergenceTest::Verdict::RoundingFloor);
}

// An update at rounding level ends the iteration below the floor level; a chord's update counts
// the steps still to come at its rate (update / (1 - rate)).
TEST(ConvergenceTest, AnUpdateAtRoundingLevelBelowTheFloorLevel) {
  ConvergenceTest t;
  t.tolerance = 1e-10;
  t.update_tolerance = 1e-12;
  EXPECT_EQ(t.judge(iterate(5e-8, 1e-8, INFINITY, 5e-13, 0.0)), ConvergenceTest::Verdict::RoundingFloor);
  EXPECT_EQ(t.judge(iterate(5e-9, 1e-8, INFINITY, 5e-13, 0.9)), ConvergenceTest::Verdict::Continue);  // 5e-12 to come
  EXPECT_EQ(t.judge(iterate(5e-9, 1e-8, INFINITY, 5e-14, 0.9)), ConvergenceTest::Verdict::RoundingFloor);
  EXPECT_EQ(t.judge(iterate(5e-6, 1e-5, INFINITY, 5e-14, 0.0)), ConvergenceTest::Verdict::Continue);  // above it
}

// The step controller from a sequence of outcomes: grow below the target, shrink by slow_shrink
// above it (not after a stale matrix), not grown after a landing, shrink by `shrink` on failure,
// always within [min, max].
TEST(StepController, FromASequenceOfOutcomes) {
  StepOptions o;
  o.min = 1e-3;
  o.max = 0.5;
  o.growth = 1.5;
  o.slow_shrink = 0.7;
  o.shrink = 0.5;
  const StepController c(o, 14);
  EXPECT_DOUBLE_EQ(c.first(2.0), 0.5);
  struct Case {
    StepOutcome outcome;
    double factor;
  };
  const Case sequence[] = {
      {{3, false, false}, 1.5},   // easy: grow
      {{14, false, false}, 1.0},  // at the target: keep
      {{20, false, false}, 0.7},  // hard: shrink
      {{20, true, false}, 1.0},   // hard on an old matrix: the step was not too long
      {{3, false, true}, 1.0},    // landed: says nothing for a longer step
  };
  double ds = 0.1;
  for (const Case& cs : sequence) {
    const double next = c.after_accepted(ds, cs.outcome);
    EXPECT_NEAR(next, ds * cs.factor, 1e-15) << cs.outcome.iterations;
    ds = next;
  }
  EXPECT_DOUBLE_EQ(c.after_accepted(0.45, {1, false, false}), 0.5);      // capped at max
  EXPECT_DOUBLE_EQ(c.after_accepted(1.2e-3, {30, false, false}), 1e-3);  // floored at min
  // a step rejected for its turn alone shrinks to the floor, never below it
  EXPECT_DOUBLE_EQ(c.after_turn(0.1), 0.05);
  EXPECT_DOUBLE_EQ(c.after_turn(1.5e-3), 1e-3);
  EXPECT_DOUBLE_EQ(c.after_turn(1e-3), 1e-3);
  EXPECT_FALSE(c.below_floor(c.after_turn(1e-3)));
  double failed = 0.1;
  int failures = 0;
  while (!c.below_floor(failed)) {
    failed = c.after_failure(failed);
    ++failures;
  }
  EXPECT_EQ(failures, 7);  // 0.1 / 2^7 = 7.8e-4 < 1e-3
}

// The landing plan: the nearest stop or bound the predicted step crosses, with its fraction of the
// step; bounds only when left from inside; none near an extrapolated fold or right after one.
TEST(Predictor, TheLandingPlanFromStopsAndAPredictedStep) {
  LandingQuery q;
  q.lambda = 0.5;
  q.s = 1.0;
  q.tlambda = 1.0;
  q.step = 2.0;
  q.direction = 1.0;  // predicted parameter 2.5
  const std::vector<double> stops = {2.0, 1.0, 3.0};
  auto land = plan_landing(q, stops, -INFINITY, INFINITY, "p");
  ASSERT_TRUE(land);
  EXPECT_EQ(land->value, 1.0);
  EXPECT_DOUBLE_EQ(land->fraction, 0.25);
  EXPECT_EQ(land->label, "p = 1");
  EXPECT_FALSE(land->end);
  // the upper bound before the first stop ends the branch there
  land = plan_landing(q, stops, -INFINITY, 0.75, "p");
  ASSERT_TRUE(land);
  EXPECT_EQ(land->value, 0.75);
  EXPECT_EQ(land->end, StopCode::UpperBound);
  // a lower bound crossed upwards (the branch starts below it) is not landed on
  EXPECT_FALSE(plan_landing(q, {}, 0.75, INFINITY, "p"));
  // no value within reach of the step
  EXPECT_FALSE(plan_landing(q, {3.0}, -INFINITY, INFINITY, "p"));
  // the tangent's parameter part falls from 1.25 to 1 over s = 0.5: it vanishes 2 further on, so a
  // stop at a fraction 0.25 of a step of 2 (0.5 along) is within half of that; one at 0.75 is not
  q.has_previous = true;
  q.previous_s = 0.5;
  q.previous_tlambda = 1.25;
  ASSERT_TRUE(plan_landing(q, {1.0}, -INFINITY, INFINITY, "p"));
  EXPECT_FALSE(plan_landing(q, {2.0}, -INFINITY, INFINITY, "p"));
  // right after a fold (the parameter part changed sign): no landing
  q.previous_tlambda = -0.5;
  EXPECT_FALSE(plan_landing(q, {1.0}, -INFINITY, INFINITY, "p"));
}

// Where a step lands on a function's zero (its value g and its slope along the step at the
// start, as fractions of the planned step ds): the linear prediction -g / slope where the zero is
// ahead, beyond 1e-3 of the step, within 1.25 of it and within the largest step.
TEST(Predictor, TheZeroLandingPlanFromAValueAndASlope) {
  // g = 1 falling at 10 per unit along the step: zero at 0.1, half the step of 0.2
  auto f = plan_zero_landing(1.0, -10.0, 0.2, 1.0);
  ASSERT_TRUE(f);
  EXPECT_DOUBLE_EQ(*f, 0.5);
  EXPECT_DOUBLE_EQ(*plan_zero_landing(-1.0, 10.0, 0.2, 1.0), 0.5);  // from below alike
  EXPECT_FALSE(plan_zero_landing(1.0, 10.0, 0.2, 1.0));             // moving away from the zero
  EXPECT_FALSE(plan_zero_landing(1.0, 0.0, 0.2, 1.0));              // not moving
  // beyond the planned step, within 1.25 of it: 0.24 = 1.2 ds lands; 0.26 = 1.3 ds does not
  EXPECT_NEAR(*plan_zero_landing(0.24, -1.0, 0.2, 1.0), 1.2, 1e-12);
  EXPECT_FALSE(plan_zero_landing(0.26, -1.0, 0.2, 1.0));
  // ... nor beyond the largest step (ds already at it)
  EXPECT_FALSE(plan_zero_landing(0.24, -1.0, 0.2, 0.2));
  EXPECT_TRUE(plan_zero_landing(0.2, -1.0, 0.2, 0.2));
  // a zero within 1e-3 of the step (the point sits on it, within rounding) is not landed on
  EXPECT_FALSE(plan_zero_landing(1e-5, -1.0, 0.2, 1.0));
  EXPECT_TRUE(plan_zero_landing(1e-3, -1.0, 0.2, 1.0));
  EXPECT_FALSE(plan_zero_landing(NAN, -1.0, 0.2, 1.0));
  EXPECT_FALSE(plan_zero_landing(1.0, -10.0, 0.0, 1.0));
}

namespace {

BranchPoint point(double s, double lambda, double tlambda, std::vector<double> monitors) {
  BranchPoint p;
  p.s = s;
  p.lambda = lambda;
  p.tlambda = tlambda;
  p.monitors = std::move(monitors);
  return p;
}

}  // namespace

// The crossings of a segment, in order: the upper bound, requested values (not the one landed on),
// monitors (the problem's are events, the stop thresholds ends; the same function twice is one
// search), folds.
// A tangent iteration's error after its correction: on a linear iteration converging at rate r the
// error after a correction of length c is about r c, and r is the ratio of successive corrections
// (c_k = r c_{k-1}); so 1e-5 after 1e-4 leaves 1e-6. Where the corrections do not fall (the first,
// or an accelerated iteration that rose) nothing is assumed: the correction itself.
TEST(TangentSolver, TheErrorLeftFromTheFallOfTheCorrections) {
  EXPECT_DOUBLE_EQ(TangentSolver::error_left(1e-5, 1e-4), 1e-6);
  EXPECT_DOUBLE_EQ(TangentSolver::error_left(6.8e-6, 7.1e-5), 6.8e-6 * 6.8e-6 / 7.1e-5);
  EXPECT_DOUBLE_EQ(TangentSolver::error_left(0.3, 0.0), 0.3);     // the first correction
  EXPECT_DOUBLE_EQ(TangentSolver::error_left(2e-5, 1e-5), 2e-5);  // a rise
  EXPECT_DOUBLE_EQ(TangentSolver::error_left(1e-5, 1e-5), 1e-5);  // no fall
  // (a geometric sequence of corrections at rate 1/8 from 1: below 1e-6 one correction earlier
  // than the correction itself)
  int with_fall = -1, plain = -1;
  for (int k = 1; k < 12; ++k) {
    const double c = std::pow(0.125, k), previous = std::pow(0.125, k - 1);
    if (with_fall < 0 && TangentSolver::error_left(c, previous) <= 1e-6) with_fall = k;
    if (plain < 0 && c <= 1e-6) plain = k;
  }
  EXPECT_EQ(with_fall, 6);  // 8^-7 = 4.8e-7
  EXPECT_EQ(plain, 7);
}

// A tangent is accurate with its error within 1e-4 of its length and the sign of its parameter part
// certain; near a fold, where that part is as small as its error, only with the error within 1e-6
// (the tolerance the whole tangent had before).
TEST(TangentSolver, AccurateWhereTheParameterPartsSignIsCertain) {
  EXPECT_TRUE(TangentSolver::accurate(5e-5, 1.0, 5e-5, 0.7));    // far from a fold
  EXPECT_FALSE(TangentSolver::accurate(2e-4, 1.0, 1e-5, 0.7));   // too far off
  EXPECT_FALSE(TangentSolver::accurate(5e-5, 1.0, 5e-5, 8e-5));  // the sign of mu uncertain
  EXPECT_TRUE(TangentSolver::accurate(5e-7, 1.0, 5e-7, 8e-7));   // ... unless the error is 1e-6
  EXPECT_TRUE(TangentSolver::accurate(5e-5, 1.0, 1e-5, 8e-5));   // mu's own error small enough
  EXPECT_TRUE(TangentSolver::accurate(5e-4, 10.0, 5e-4, 3.0));   // relative to the length
}

TEST(EventDetector, TheCrossingsOfASegment) {
  ContinuationOptions o;
  o.parameter = "p";
  o.stop.upper = 1.9;
  o.events.stops = {1.2, 1.5};
  const BranchPoint cur = point(0.0, 1.0, 0.8, {0.3, -1.0, 0.3});
  const BranchPoint nxt = point(1.0, 2.0, -0.2, {-0.1, -0.5, -0.1});
  const std::vector<std::string> names = {"g", "h", "g < stop_below"};
  Landing land;
  land.value = 1.5;
  const auto c = detect_crossings(cur, nxt, land, o, names, 2);
  ASSERT_EQ(c.size(), 5u);
  EXPECT_EQ(c[0].kind, PointKind::End);
  EXPECT_EQ(c[0].target.value, 1.9);
  EXPECT_EQ(c[0].end, StopCode::UpperBound);
  EXPECT_EQ(c[1].kind, PointKind::Requested);
  EXPECT_EQ(c[1].target.value, 1.2);
  EXPECT_EQ(c[1].label, "p = 1.2");
  EXPECT_EQ(c[2].kind, PointKind::Event);
  EXPECT_EQ(c[2].target.monitor, 0);
  EXPECT_EQ(c[3].kind, PointKind::End);  // the stop threshold on the same function as monitor 0
  EXPECT_EQ(c[3].end, StopCode::StopObservable);
  EXPECT_EQ(c[3].same_as, 2);
  EXPECT_EQ(c[4].kind, PointKind::Fold);
  EXPECT_EQ(c[4].label, "max");
  // natural continuation locates no folds
  o.method = ContinuationOptions::Method::Natural;
  EXPECT_EQ(detect_crossings(cur, nxt, land, o, names, 2).size(), 4u);
  // a monitor that vanishes exactly at nxt (a landed stop) is located at nxt
  const BranchPoint on = point(1.0, 2.0, 0.8, {0.0, -1.0, 0.0});
  const auto z = detect_crossings(cur, on, land, o, names, 2);
  ASSERT_EQ(z.size(), 4u);  // the bound, the stop, monitor 0 and its threshold
  EXPECT_TRUE(z[2].at_next);
  EXPECT_TRUE(z[3].at_next);
  // a step that landed on the threshold's zero: its value there is rounding, of either sign (here
  // the sign it started with, no crossing by sign), and the zero is nxt's, with that of monitor
  // 0, the same function
  Landing zero;
  zero.monitor = 2;
  zero.end = StopCode::StopObservable;
  zero.value = NAN;
  for (double rounding : {1e-15, -1e-15}) {
    const BranchPoint landed = point(1.0, 1.4, 0.8, {rounding, -1.0, rounding});
    const auto l = detect_crossings(cur, landed, zero, o, names, 2);
    ASSERT_EQ(l.size(), 3u) << rounding;  // the stop at 1.2, monitor 0 and its threshold
    EXPECT_EQ(l[1].target.monitor, 0);
    EXPECT_TRUE(l[1].at_next);
    EXPECT_EQ(l[2].target.monitor, 2);
    EXPECT_TRUE(l[2].at_next);
    EXPECT_EQ(l[2].end, StopCode::StopObservable);
  }
}

// Located points come in order along the branch; an event that is also the located end of the
// stop observable is reported once, as the end.
TEST(EventDetector, LocatedPointsInOrderAndAnEndReportedOnce) {
  std::vector<LocatedPoint> located(3);
  located[0].point = point(0.7, 1.7, 1, {});
  located[0].point.kind = PointKind::Event;
  located[1].point = point(0.3, 1.3, 1, {});
  located[1].point.kind = PointKind::Requested;
  located[2].point = point(0.7 + 1e-5, 1.7 + 1e-9, 1, {});
  located[2].point.kind = PointKind::End;
  located[2].end = StopCode::StopObservable;
  order_located(located, 1.0, 1e-8);
  ASSERT_EQ(located.size(), 2u);
  EXPECT_EQ(located[0].point.kind, PointKind::Requested);
  EXPECT_EQ(located[1].point.kind, PointKind::End);
}

// Bisection finds the adjacent pair where a property first differs from its first value, with
// about log2(n) evaluations; a failed evaluation gives nothing.
TEST(Bracket, BisectionFindsTheChange) {
  const std::vector<int> counts = {0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1};
  int evaluations = 0;
  const auto pair = bisect_change(counts.size(), 0, [&](size_t i) {
    ++evaluations;
    return counts[i];
  });
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->first, 4u);
  EXPECT_EQ(pair->second, 5u);
  EXPECT_LE(evaluations, 4);
  EXPECT_FALSE(bisect_change(counts.size(), 0, [](size_t) { return -1; }));
  const auto adjacent = bisect_change(2, 0, [](size_t) { return -1; });  // nothing to evaluate
  ASSERT_TRUE(adjacent);
  EXPECT_EQ(adjacent->second, 1u);
}

namespace {

// A branch of points s = 0, 1, 2, ... whose determinant sign is +1 before s = crossing and -1 after.
struct SignedBranch {
  double crossing;
  std::map<double, int> probed;  // s -> sign, the probes made
  BranchPoint at(double s, bool sampled) const {
    BranchPoint p = point(s, s, 1.0, {});
    p.bordered_det_sign = sampled ? sign(s) : 0;
    return p;
  }
  int sign(double s) const { return s < crossing ? 1 : -1; }
  int probe(BranchPoint& p) {
    probed[p.s] = sign(p.s);
    p.bordered_det_sign = sign(p.s);
    return p.bordered_det_sign;
  }
};

}  // namespace

// The branch-point monitor from given signs: a change between two signs a few rows apart is
// narrowed to one step by probing the rows in between (bisection); a sign from an iterate of a
// step (not exact at its point) starts the bracket one row earlier.
TEST(BranchPointMonitor, ASignChangeIsBracketedByProbingTheRowsBetween) {
  SignedBranch b{6.5, {}};
  BranchPointMonitor m;
  m.restart(b.at(0, true));
  auto probe = [&](BranchPoint& p) { return b.probe(p); };
  std::optional<std::pair<BranchPoint, BranchPoint>> change;
  for (int s = 1; s <= 9 && !change; ++s) {
    const bool sampled = s == 3 || s == 9;  // factorisations at rows 3 and 9 only
    change = m.accepted(b.at(s, sampled), false, probe);
  }
  ASSERT_TRUE(change);
  EXPECT_EQ(change->first.s, 6.0);
  EXPECT_EQ(change->second.s, 7.0);
  EXPECT_EQ(change->first.bordered_det_sign, 1);
  EXPECT_EQ(change->second.bordered_det_sign, -1);
  // the bracket started at row 2 (row 3's sign was an iterate's) and probed about log2(8) rows
  EXPECT_LE(b.probed.size(), 3u);
  for (const auto& [s, sign] : b.probed) EXPECT_GT(s, 2.0);
}

// Without a sign for kBranchPointProbeRows rows (a chord that never renews), one is probed; and at
// the branch's last point.
TEST(BranchPointMonitor, ProbesAfterTooManyRowsWithoutASign) {
  SignedBranch b{100.0, {}};
  BranchPointMonitor m;
  m.restart(b.at(0, true));
  int probes = 0;
  for (int s = 1; s <= 3 * kBranchPointProbeRows; ++s) {
    BranchPoint p = b.at(s, false);
    if (m.needs_probe(p, false)) {
      ++probes;
      b.probe(p);
    }
    EXPECT_FALSE(m.accepted(p, true, [&](BranchPoint& q) { return b.probe(q); }));
  }
  EXPECT_EQ(probes, 3);
  EXPECT_TRUE(m.needs_probe(b.at(31, false), true));  // the last point
  EXPECT_FALSE(m.needs_probe(b.at(31, true), true));  // has its own sign
}

// Every step signed (no kept factorisation): the bracket is the step itself, nothing probed.
TEST(BranchPointMonitor, EveryStepSignedNeedsNoProbe) {
  SignedBranch b{4.5, {}};
  BranchPointMonitor m;
  m.restart(b.at(0, true));
  std::optional<std::pair<BranchPoint, BranchPoint>> change;
  for (int s = 1; s <= 6 && !change; ++s)
    change = m.accepted(b.at(s, true), true, [&](BranchPoint& q) { return b.probe(q); });
  ASSERT_TRUE(change);
  EXPECT_EQ(change->first.s, 4.0);
  EXPECT_EQ(change->second.s, 5.0);
  EXPECT_TRUE(b.probed.empty());
}

namespace {

class CountingAnalysis final : public PointAnalysis {
 public:
  explicit CountingAnalysis(int every) : every_(every) {}
  std::vector<std::string> column_names() const override { return {}; }
  std::string count_name() const override { return "unstable"; }
  Status analyse(Problem&, const Vector&, PointAnalysisResult&, SparseLU*) override { return {}; }
  int every() const override { return every_; }

 private:
  int every_;
};

}  // namespace

// Spectra every 4 points and at the last step; a change of the count between two analysed points
// is bracketed by analysing the points in between (bisection).
TEST(SpectrumScheduler, EveryNPointsAndAChangeBracketedByBisection) {
  CountingAnalysis analysis(4);
  SpectrumScheduler s(&analysis);
  EXPECT_FALSE(s.due(1, 100));
  EXPECT_TRUE(s.due(4, 100));
  EXPECT_TRUE(s.due(7, 7));
  auto count_at = [](double lambda) { return lambda < 2.5 ? 0 : 1; };
  BranchPoint start = point(0, 0, 1, {});
  start.index = 0;
  start.analysed = true;
  start.count = 0;
  s.restart(start, false);
  int analysed = 0;
  auto analyse = [&](BranchPoint& p) {
    ++analysed;
    p.analysed = true;
    p.count = count_at(p.lambda);
  };
  std::vector<BranchPoint> rows;
  for (int k = 1; k <= 3; ++k) {
    BranchPoint p = point(k, k, 1, {});
    p.index = k;
    s.reported(p);
    rows.push_back(p);
  }
  BranchPoint cur = rows.back(), nxt = point(4, 4, 1, {});
  analyse(nxt);
  const auto change = s.change_at(cur, nxt, analyse);
  ASSERT_TRUE(change);
  ASSERT_TRUE(change->bracketed);
  EXPECT_EQ(change->a->lambda, 2.0);
  EXPECT_EQ(change->b->lambda, 3.0);
  EXPECT_FALSE(change->this_step);
  EXPECT_EQ(change->description, "unstable 0 -> 1");
  EXPECT_LE(analysed, 3);  // nxt and two in between
}

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
