// Matrix pairs (J, B) with known spectra for the tests of stability/EigenSolver: the 1D Laplacian
// with consistent mass, rotation blocks with algebraic unknowns, and the checks the tests share
// (relative residual of a pair, nearest values, one-to-one matching against expected values).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "core/Types.hpp"
#include "stability/EigenSolver.hpp"

namespace keller::test {

using Complex = std::complex<double>;
using Triplets = std::vector<Eigen::Triplet<double, int>>;
inline SparseMatrix from_triplets(int rows, int cols, const Triplets& t) {
  SparseMatrix A(rows, cols);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

// -u'' on (0, 1) with linear elements on `elements` uniform elements: element stiffness
// (1/h)[1 -1; -1 1] and consistent mass (h/6)[2 1; 1 2], all nodes 0..elements.
struct Laplacian1D {
  int elements;
  double h;
  Triplets stiffness, mass;  // full (elements + 1) x (elements + 1) matrices
  explicit Laplacian1D(int e) : elements(e), h(1.0 / e) {
    for (int k = 0; k < e; ++k)
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          stiffness.emplace_back(k + a, k + b, (a == b ? 1.0 : -1.0) / h);
          mass.emplace_back(k + a, k + b, (a == b ? 2.0 : 1.0) * h / 6.0);
        }
  }
  // The discrete eigenvalues sigma_j = (6/h^2)(1 - cos(j pi h))/(2 + cos(j pi h)), j = 1..elements-1.
  double sigma(int j) const {
    const double c = std::cos(j * std::numbers::pi * h);
    return 6.0 / (h * h) * (1.0 - c) / (2.0 + c);
  }
  // Interior unknowns only (nodes 1..elements-1 -> 0..elements-2).
  void interior(SparseMatrix& K, SparseMatrix& M) const {
    Triplets k, m;
    for (const auto& t : stiffness)
      if (t.row() > 0 && t.row() < elements && t.col() > 0 && t.col() < elements)
        k.emplace_back(t.row() - 1, t.col() - 1, t.value());
    for (const auto& t : mass)
      if (t.row() > 0 && t.row() < elements && t.col() > 0 && t.col() < elements)
        m.emplace_back(t.row() - 1, t.col() - 1, t.value());
    K = from_triplets(elements - 1, elements - 1, k);
    M = from_triplets(elements - 1, elements - 1, m);
  }
};

inline double relative_residual(const SparseMatrix& J, const SparseMatrix& B, Complex sigma,
                                const Eigen::VectorXcd& phi) {
  const Eigen::MatrixXcd Jd = Eigen::MatrixXd(J).cast<Complex>(), Bd = Eigen::MatrixXd(B).cast<Complex>();
  return (Jd * phi - sigma * (Bd * phi)).norm() / ((Jd.norm() + std::abs(sigma) * Bd.norm()) * phi.norm());
}

// The `count` values of `all` nearest s.
inline std::vector<Complex> nearest(std::vector<Complex> all, Complex s, int count) {
  std::sort(all.begin(), all.end(), [s](Complex a, Complex b) { return std::abs(a - s) < std::abs(b - s); });
  all.resize(count);
  return all;
}

// Largest relative distance from each computed value to the nearest of `expected`, and whether
// every expected value is matched (a one-to-one check: the values are distinct).
inline double match_error(const EigenResult& r, const std::vector<Complex>& expected) {
  double worst = 0;
  for (Complex e : expected) {
    double best = INFINITY;
    for (const auto& p : r.pairs) best = std::min(best, std::abs(p.value - e) / std::abs(e));
    worst = std::max(worst, best);
  }
  for (const auto& p : r.pairs) {
    double best = INFINITY;
    for (Complex e : expected) best = std::min(best, std::abs(p.value - e) / std::abs(e));
    worst = std::max(worst, best);
  }
  return worst;
}

// Block upper-triangular J (2x2 diagonal blocks [a -b; b a], eigenvalues a +- ib, coupled to the
// next block by 0.5) followed by `algebraic` unknowns q with equations 2 q_m + u_{3m} = 0 (zero rows
// of B). J = [A 0; D E] is block lower triangular in (u, q), so det(J - sigma B) = det(A - sigma I)
// det(E): the finite spectrum is exactly {a_k +- i b_k}, and the eigenvectors have q = -E^-1 D u != 0.
struct RotationBlocks {
  int blocks, algebraic;
  SparseMatrix J, B;
  std::vector<Complex> spectrum;
  RotationBlocks(int nb, int na) : blocks(nb), algebraic(na) {
    const int n = 2 * nb + na;
    Triplets j, b;
    for (int k = 0; k < nb; ++k) {
      const double a = 0.5 * k - 3.0, w = 1.0 + 0.2 * k;
      j.emplace_back(2 * k, 2 * k, a);
      j.emplace_back(2 * k, 2 * k + 1, -w);
      j.emplace_back(2 * k + 1, 2 * k, w);
      j.emplace_back(2 * k + 1, 2 * k + 1, a);
      if (k + 1 < nb) j.emplace_back(2 * k, 2 * k + 2, 0.5);
      b.emplace_back(2 * k, 2 * k, 1.0);
      b.emplace_back(2 * k + 1, 2 * k + 1, 1.0);
      spectrum.emplace_back(a, w);
      spectrum.emplace_back(a, -w);
    }
    for (int m = 0; m < na; ++m) {
      j.emplace_back(2 * nb + m, 2 * nb + m, 2.0);
      j.emplace_back(2 * nb + m, 3 * m, 1.0);
    }
    J = from_triplets(n, n, j);
    B = from_triplets(n, n, b);
  }
};

}  // namespace keller::test
