// When an iteration has converged or stopped at the rounding floor (core/ConvergenceTest), from
// given iterates.
#include <gtest/gtest.h>

#include <cmath>

#include "core/ConvergenceTest.hpp"

using namespace keller;

namespace {

ConvergenceTest::Iterate iterate(double residual, double previous, double before = INFINITY, double update = INFINITY,
                                 double contraction = 0.0, double best = INFINITY) {
  ConvergenceTest::Iterate it;
  it.best = best;
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

// A residual that grows is no floor: the corrector of a point located 6e-8 from a Turing branch
// point of the Brusselator went 4.3e-11 -> 3.8e-10 -> 2.7e-8 along J's null vector (its update
// 2.3e-4), which stopped the slow chord as "stalled" and gave a point 2.3e-4 off the branch. A
// stall counts only within kFloorWander (10) of the smallest residual the iteration reached.
TEST(ConvergenceTest, AResidualFarAboveTheBestOneIsGrowingNotAtTheFloor) {
  ConvergenceTest t;
  t.tolerance = 1e-10;
  t.update_tolerance = 1e-12;
  t.slow = true;
  EXPECT_EQ(t.judge(iterate(2.7e-8, 3.8e-10, 4.3e-11, 2.3e-4, 1.0, 4.3e-11)), ConvergenceTest::Verdict::Continue);
  // the same history at a floor: the best residual near this one
  EXPECT_EQ(t.judge(iterate(2.7e-8, 2.8e-8, 2.9e-8, 1e-6, 1.0, 2.7e-8)), ConvergenceTest::Verdict::RoundingFloor);
  // wandering within the band (9x the best) still stalls there
  EXPECT_EQ(t.judge(iterate(9e-9, 8e-9, 9.5e-9, 1e-6, 1.0, 1e-9)), ConvergenceTest::Verdict::RoundingFloor);
  // an update at rounding level ends the iteration wherever the residual is
  EXPECT_EQ(t.judge(iterate(2.7e-8, 3.8e-10, 4.3e-11, 5e-14, 0.0, 4.3e-11)), ConvergenceTest::Verdict::RoundingFloor);
}
