// The accuracy test of a tangent by iteration (continuation/engine/TangentSolver) on given
// corrections.
#include <gtest/gtest.h>

#include <cmath>

#include "continuation/engine/TangentSolver.hpp"

using namespace keller;

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
