// The policy that keeps a shift-invert monitor's unstable eigenvalues inside its computed set
// (stability/SpectrumEdge), on synthetic spectra.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "stability/SpectrumEdge.hpp"

using namespace keller;
using C = std::complex<double>;

// Stable states, and unstable eigenvalues with a stable one beyond them: the set is enough.
TEST(SpectrumEdge, UnstableEigenvaluesInsideTheSetAreSeparated) {
  EXPECT_TRUE(spectrum_edge_separated({C(0.1), C(0.5), C(2.0)}, 0.0, 3));
  EXPECT_TRUE(spectrum_edge_separated({C(-0.1), C(0.5), C(-1.0), C(2.0)}, 0.0, 4));
  EXPECT_EQ(count_to_separate({C(-0.1), C(0.5), C(-1.0), C(2.0)}, 0.0, 4, 32), 4);
}

// The farthest computed eigenvalue unstable: another may lie just beyond; the set doubles.
TEST(SpectrumEdge, AnUnstableEigenvalueAtTheEdgeGrowsTheSet) {
  EXPECT_FALSE(spectrum_edge_separated({C(0.1), C(-0.3)}, 0.0, 2));
  EXPECT_EQ(count_to_separate({C(0.1), C(-0.3)}, 0.0, 2, 32), 4);
  EXPECT_EQ(count_to_separate({C(-0.1), C(-0.3)}, 0.0, 2, 32), 4);
  // up to the cap, and no further
  EXPECT_EQ(count_to_separate({C(-0.1), C(-0.3), C(0.2), C(-0.4)}, 0.0, 4, 6), 6);
  EXPECT_EQ(count_to_separate({C(-0.1), C(-0.3), C(0.2), C(-0.4), C(0.1), C(-0.5)}, 0.0, 6, 6), 6);
}

// A stable eigenvalue as far from the shift as the unstable one (a double eigenvalue, or the two
// halves of a conjugate pair split by the imaginary axis of a complex shift) does not separate it.
TEST(SpectrumEdge, AStableEigenvalueLevelWithTheUnstableOneDoesNotSeparate) {
  EXPECT_FALSE(spectrum_edge_separated({C(0.1), C(-0.5), C(0.5)}, 0.0, 3));
  EXPECT_FALSE(spectrum_edge_separated({C(0.1), C(-0.5), C(0.5 * (1 + 1e-7))}, 0.0, 3));
  EXPECT_TRUE(spectrum_edge_separated({C(0.1), C(-0.5), C(0.5 * (1 + 1e-5))}, 0.0, 3));
}

// Distances are from the shift: near a complex shift, a pair far from it does not count as near.
TEST(SpectrumEdge, DistancesAreMeasuredFromTheShift) {
  const C s(0.0, 2.0);
  // the unstable eigenvalue -0.1 + 2i is the nearest to s; a stable one farther away separates it
  EXPECT_TRUE(spectrum_edge_separated({C(-0.1, 2.0), C(0.3, 2.0), C(0.3, -2.0)}, s, 3));
  // its conjugate -0.1 - 2i is the farthest: not separated
  EXPECT_FALSE(spectrum_edge_separated({C(-0.1, 2.0), C(0.3, 2.0), C(-0.1, -2.0)}, s, 3));
}

// Fewer eigenvalues than asked for: the pencil's finite ones are exhausted, nothing lies beyond.
TEST(SpectrumEdge, AnExhaustedPencilIsSeparated) {
  EXPECT_TRUE(spectrum_edge_separated({C(-0.1), C(-0.3)}, 0.0, 4));
  EXPECT_EQ(count_to_separate({C(-0.1), C(-0.3)}, 0.0, 4, 32), 4);
}

// Merging the sets of several shifts: an eigenvalue two shifts found counts once, a double one
// (two independent modes of a symmetric domain) twice, however the shifts found its copies.
TEST(SpectrumEdge, AMultipleEigenvalueIsMergedAsOftenAsOneShiftFoundIt) {
  // one shift: a double eigenvalue stays double
  EXPECT_EQ(values_to_merge({}, {C(-0.0133), C(-0.0133 * (1 + 1e-12)), C(0.02)}), (std::vector<size_t>{0, 1, 2}));
  // a second shift finds one copy of it again, and a new value: only the new value is added
  EXPECT_EQ(values_to_merge({C(-0.0133), C(-0.0133), C(0.02)}, {C(-0.0133), C(0.5)}), (std::vector<size_t>{1}));
  // a second shift finds both copies where the first found one: the second copy is added
  EXPECT_EQ(values_to_merge({C(-0.0133), C(0.02)}, {C(-0.0133), C(-0.0133)}), (std::vector<size_t>{1}));
  // values 1e-6 apart are two eigenvalues
  EXPECT_EQ(values_to_merge({C(1.0)}, {C(1.0 + 1e-6)}), (std::vector<size_t>{0}));
}

// The unstable modes of the last analysis must be in the next set: a mode whose eigenvector has
// no counterpart (share below 1/2) is lost; a double eigenvalue's modes rotated within their
// plane, and a vector's scale and phase, are not.
TEST(SpectrumEdge, AnUnstableModeMissingFromTheNextSetIsLost) {
  using V = Eigen::VectorXcd;
  V e1 = V::Zero(4), e2 = V::Zero(4), e3 = V::Zero(4);
  e1[0] = 1.0;
  e2[1] = 1.0;
  e3[2] = 1.0;
  EXPECT_FALSE(unstable_mode_lost({}, {e1}));
  EXPECT_FALSE(unstable_mode_lost({e1}, {e2, std::complex<double>(0.0, -3.0) * e1}));
  EXPECT_TRUE(unstable_mode_lost({e1}, {e2, e3}));
  // a double eigenvalue's plane: e1 found as (e1 + e2) / sqrt 2 and (e1 - e2) / sqrt 2
  EXPECT_FALSE(unstable_mode_lost({e1, e2}, {(e1 + e2) / std::sqrt(2.0), (e1 - e2) / std::sqrt(2.0), e3}));
  // a mode mostly elsewhere: share 0.2
  EXPECT_TRUE(unstable_mode_lost({e1}, {std::sqrt(0.2) * e1 + std::sqrt(0.8) * e2, e3}));
}

// A set from a shift almost at an eigenvalue is computed again from a moved shift: where J - sB was
// singular, where the solver failed with inaccurate pairs, and where it converged on fewer pairs
// than asked (a double zero at a symmetric branch point: 2 of 12); not for a good set, nor for a
// failure whose pairs are all accurate (the solver's own limit, not the shift).
TEST(SpectrumEdge, AShiftAtAnEigenvalueIsMoved) {
  EXPECT_FALSE(needs_moved_shift(true, false, false, 12, 12));
  EXPECT_TRUE(needs_moved_shift(false, false, true, 0, 12));
  EXPECT_TRUE(needs_moved_shift(false, true, false, 12, 12));
  EXPECT_FALSE(needs_moved_shift(false, false, false, 12, 12));
  EXPECT_TRUE(needs_moved_shift(true, false, false, 2, 12));
}

// The move: a quarter of the spread of the values found, or of the last point's where that is
// wider (a double zero's two values, 2e-15 from the shift, span nothing); 1 with neither.
TEST(SpectrumEdge, AShiftIsMovedByAQuarterOfTheSpread) {
  EXPECT_DOUBLE_EQ(shift_move({C(-0.1), C(0.4), C(0.2, 0.3)}, 0.0, 0.0), 0.1);
  EXPECT_DOUBLE_EQ(shift_move({C(2e-15), C(3e-15)}, 0.0, 0.36), 0.09);
  EXPECT_DOUBLE_EQ(shift_move({C(1.5)}, 1.0, 0.0), 0.125);
  EXPECT_DOUBLE_EQ(shift_move({}, 0.0, 0.0), 1.0);
}
