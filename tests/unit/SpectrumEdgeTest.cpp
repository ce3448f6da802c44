// The policy that keeps a shift-invert monitor's unstable eigenvalues inside its computed set
// (stability/SpectrumEdge), on synthetic spectra.
#include <gtest/gtest.h>

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
