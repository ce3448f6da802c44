// When a chord should get a new Jacobian (core/RenewalPolicy), from given residual histories.
#include <gtest/gtest.h>

#include <cmath>

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
