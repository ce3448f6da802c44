// The central-difference grid the 1D test problems share (Bratu, pitchfork): n uniform intervals
// on (0, 1), the n - 1 interior values as unknowns, u = 0 at both ends.
#pragma once

#include <vector>

#include "core/SolutionFields.hpp"
#include "core/Types.hpp"

namespace keller {

// Largest grid of the 1D test problems' scene keys: 10^7 intervals (a few hundred MB of
// Jacobian); the sparse matrices index their entries with int, so much more would overflow.
inline constexpr long max_grid_intervals = 10'000'000;

}  // namespace keller

namespace keller::grid1d {

// Pattern of a tridiagonal m x m matrix (values zero).
inline SparseMatrix tridiagonal_pattern(int m) {
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < m; ++i)
    for (int j = i > 0 ? i - 1 : 0; j <= (i + 1 < m ? i + 1 : m - 1); ++j) t.emplace_back(i, j, 0.0);
  SparseMatrix p(m, m);
  p.setFromTriplets(t.begin(), t.end());
  p.makeCompressed();
  return p;
}

// A on `pattern` with diagonal `diagonal` and every off-diagonal entry `off`.
inline void fill_tridiagonal(const SparseMatrix& pattern, const Vector& diagonal, double off, SparseMatrix& A) {
  A = pattern;
  for (int c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(A, c); it; ++it) it.valueRef() = it.row() == c ? diagonal[c] : off;
}

// u(x) on the grid with its boundary values, for output.
inline NamedArray profile(const Vector& u, int intervals) {
  NamedArray a{"profile", "u(x) on the grid, boundary values included", Eigen::MatrixXd(intervals + 1, 2), {"x", "u"}};
  for (int i = 0; i <= intervals; ++i) {
    a.values(i, 0) = static_cast<double>(i) / intervals;
    a.values(i, 1) = (i == 0 || i == intervals) ? 0.0 : u[i - 1];
  }
  return a;
}

}  // namespace keller::grid1d
