// The landing plans of the predictor (continuation/engine/Predictor) from given stops, values and
// slopes and a predicted step.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "continuation/engine/Predictor.hpp"

using namespace keller;

// The landing plan: the nearest stop or bound the predicted step crosses or falls a little short of,
// with its fraction of the step; bounds only when left from inside; none near an extrapolated fold
// or right after one.
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
  // a value a little beyond the step (1.25 of it at most, within the largest step) is landed on
  // by a longer step: 3 lies 2.5 ahead of 0.5, 1.25 times the predicted 2
  land = plan_landing(q, {3.0}, -INFINITY, INFINITY, "p");
  ASSERT_TRUE(land);
  EXPECT_DOUBLE_EQ(land->fraction, 1.25);
  land = plan_landing(q, {3.0}, -INFINITY, 2.9, "p");  // the upper bound comes first: the branch ends there
  ASSERT_TRUE(land);
  EXPECT_EQ(land->end, StopCode::UpperBound);
  EXPECT_DOUBLE_EQ(land->fraction, 1.2);
  // no value within reach of the step: 1.3 of it, or a stretched step longer than the largest
  EXPECT_FALSE(plan_landing(q, {3.1}, -INFINITY, INFINITY, "p"));
  q.max_step = 2.4;
  EXPECT_FALSE(plan_landing(q, {3.0}, -INFINITY, INFINITY, "p"));
  EXPECT_TRUE(plan_landing(q, {2.5}, -INFINITY, INFINITY, "p"));  // (not stretched: the predicted value itself)
  q.max_step = INFINITY;
  // nor one behind the step's start
  EXPECT_FALSE(plan_landing(q, {0.25}, -INFINITY, INFINITY, "p"));
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
