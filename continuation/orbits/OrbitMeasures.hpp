// What is measured on a periodic orbit, as pure functions of its samples and multipliers: the
// bifurcation counts and test functions of its Floquet multipliers, and the range of a periodic
// signal from its samples (continuation/orbits/OrbitContinuation reports and locates with them).
#pragma once

#include <complex>
#include <optional>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"

namespace keller {

// The bifurcation counts of an orbit's multipliers (the trivial one left out): real ones beyond
// +1 and -1, complex pairs outside the unit circle, and all unstable ones.
struct MultiplierCounts {
  int above_plus_one = 0, below_minus_one = 0, pairs_outside = 0, unstable = 0;
  static MultiplierCounts of(const std::vector<std::complex<double>>& multipliers, int trivial);
};
// The test functions whose zeros are the bifurcations (of the multiplier nearest the crossing):
// +1 crossing mu - 1 of the real multiplier nearest 1 (the trivial left out), -1 crossing mu + 1
// of the real one nearest -1, unit circle |mu| - 1 of the complex pair nearest it; NaN where there
// is no such multiplier. `kind`: PointKind::Fold (+1), PeriodDoubling (-1), NeimarkSacker.
double multiplier_test(const std::vector<std::complex<double>>& multipliers, int trivial, PointKind kind);

// max - min of a periodic signal sampled at times t_0 = 0 < t_1 < ... < t_m = T (x_m = x_0): each
// extreme sample refined by the parabola through it and its neighbours (wrapping round the period),
// so that the range of a smooth signal errs by O(h^3) instead of the samples' O(h^2).
double periodic_range(const std::vector<double>& t, const std::vector<double>& x);

// The period of an oscillating signal sampled at increasing times t (a time integration's
// observable): over the samples of the second half of the time span, the mean spacing of the last
// (at most five) upward crossings of the mid level (max + min) / 2, each crossing by linear
// interpolation. Nothing where there are fewer than three crossings, or the signal does not vary.
std::optional<double> oscillation_period(const std::vector<double>& t, const std::vector<double>& y);

}  // namespace keller
