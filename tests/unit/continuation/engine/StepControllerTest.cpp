// The step controller (continuation/engine/StepController) from a sequence of outcomes, and its
// verdict on the turn of the tangent over a step.
#include <gtest/gtest.h>

#include <cmath>

#include "continuation/engine/StepController.hpp"

using namespace keller;

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
  // a step rejected for its turn alone shrinks so that, at the curvature it showed, it would turn
  // by 3/4 of the limit (20 degrees): 25 degrees -> 0.6 of it, 60 degrees -> 0.25; to the floor,
  // never below it
  const double deg = M_PI / 180.0;
  EXPECT_DOUBLE_EQ(c.after_turn(0.1, 25 * deg), 0.1 * 0.6);
  EXPECT_DOUBLE_EQ(c.after_turn(0.1, 60 * deg), 0.1 * 0.25);
  EXPECT_DOUBLE_EQ(c.after_turn(0.1, 21 * deg) / 0.1, 15.0 / 21.0);
  EXPECT_DOUBLE_EQ(c.after_turn(1.5e-3, 25 * deg), 1e-3);
  EXPECT_DOUBLE_EQ(c.after_turn(1e-3, 25 * deg), 1e-3);
  EXPECT_FALSE(c.below_floor(c.after_turn(1e-3, 90 * deg)));
  // (an angle within the limit is no turn rejection: the failure's factor)
  EXPECT_DOUBLE_EQ(c.after_turn(0.1, 10 * deg), 0.05);
  double failed = 0.1;
  int failures = 0;
  while (!c.below_floor(failed)) {
    failed = c.after_failure(failed);
    ++failures;
  }
  EXPECT_EQ(failures, 7);  // 0.1 / 2^7 = 7.8e-4 < 1e-3
}

// The turn of the tangent over a step (limit 20 degrees): a sharper one rejects an arclength step,
// which is tried shorter, down to the floor, where it is passed if its point lies within two
// steps of the last (the step's own) and is a failed step if it lies further; a natural step that
// turns sharply above the floor has jumped to another branch (a failed step).
TEST(StepController, TheTurnOfTheTangentOverAStep) {
  StepOptions o;
  o.min = 1e-3;
  o.max_angle_degrees = 20.0;
  const StepController c(o, 14);
  const double degree = M_PI / 180.0;
  EXPECT_EQ(c.judge_turn(10 * degree, 0.1, 0.1, true), TurnVerdict::Passed);
  EXPECT_EQ(c.judge_turn(20 * degree, 0.1, 0.1, true), TurnVerdict::Passed);  // at the limit
  EXPECT_EQ(c.judge_turn(25 * degree, 0.1, 0.1, true), TurnVerdict::Shorter);
  EXPECT_EQ(c.judge_turn(25 * degree, 0.1, 0.1, false), TurnVerdict::Jumped);
  EXPECT_EQ(c.judge_turn(25 * degree, 1.01e-3, 1e-3, true), TurnVerdict::Shorter);  // just above the floor
  // at the floor
  EXPECT_EQ(c.judge_turn(90 * degree, 1e-3, 1.5e-3, true), TurnVerdict::Passed);
  EXPECT_EQ(c.judge_turn(90 * degree, 1e-3, 2e-3, true), TurnVerdict::Passed);  // two steps: still its own
  EXPECT_EQ(c.judge_turn(90 * degree, 1e-3, 2.1e-3, true), TurnVerdict::Far);
  EXPECT_EQ(c.judge_turn(90 * degree, 1e-3, 1.0, false), TurnVerdict::Passed);
}
