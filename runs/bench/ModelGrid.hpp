// A model sparse pattern shared by bench_orderings and the ordering tests (tests/unit/FillOrderingTest): the
// Laplacian-like matrix of an nx x ny grid of points with the 5-point (or 9-point) stencil, diagonally dominant
// (nonsingular) with slightly unsymmetric values; with upper_only, only the entries on and above
// the diagonal (an unsymmetric pattern).
#pragma once

#include <vector>

#include "core/Types.hpp"

namespace keller::bench {

inline SparseMatrix model_grid(int nx, int ny, bool nine_point = false, bool upper_only = false) {
  std::vector<Eigen::Triplet<double, int>> t;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int k = i + nx * j;
      t.emplace_back(k, k, 9.0);
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int a = i + di, b = j + dj, m = a + nx * b;
          if ((di == 0 && dj == 0) || a < 0 || a >= nx || b < 0 || b >= ny) continue;
          if (!nine_point && di != 0 && dj != 0) continue;
          if (upper_only && m < k) continue;
          t.emplace_back(k, m, di != 0 && dj != 0 ? -0.5 : -1.0 - 0.01 * di);
        }
    }
  SparseMatrix A(nx * ny, nx * ny);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

}  // namespace keller::bench
