// Forward-mode automatic differentiation for element kernels: Eigen's AutoDiffScalar with a
// fixed-size derivative vector, and the few helpers kernels use so that one templated kernel
// serves double evaluation, exact Jacobians (Dual<N>) and parameter derivatives (Dual<1>).
//
// runs/bench/bench_dual.cpp times this against a hand-written dual type on the Newtonian flow
// kernel; Eigen's expression templates win (about 1.7x faster on M2), so this is the type used.
// Kernels must store intermediate results in named variables of type T, never `auto`: an
// AutoDiffScalar expression holds references to its operands.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <unsupported/Eigen/AutoDiff>

namespace keller {

template <int N>
using Dual = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;

inline double value_of(double x) { return x; }
template <class D>
double value_of(const Eigen::AutoDiffScalar<D>& x) {
  return x.value();
}

// A dual variable with value v and unit derivative in direction i.
template <int N>
Dual<N> make_variable(double v, int i) {
  return Dual<N>(v, N, i);
}

inline bool is_finite(double x) { return std::isfinite(x); }
template <class D>
bool is_finite(const Eigen::AutoDiffScalar<D>& x) {
  return std::isfinite(x.value()) && x.derivatives().allFinite();
}

}  // namespace keller
