// Shift-invert eigen-solver of stability/: known spectra of J phi = sigma B phi with regular and
// singular B, real and complex shifts, the unpacking of conjugate pairs, (the solver's behaviour:
// tests/unit/EigenSolverRunTest.cpp). Tolerances: ARPACK's tolerance 1e-12 bounds the relative error of the Ritz values
// nu = 1/(sigma - s) of the wanted (largest) nu, so sigma is good to about 1e-12 |sigma - s|; the tests ask 1e-10.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "core/SparseLU.hpp"
#include "stability/EigenSolver.hpp"
#include "support/SpectrumTestProblems.hpp"

using namespace keller;
using namespace keller::test;

TEST(EigenSolver, LaplacianSmallestEigenvalues) {
  const Laplacian1D lap(100);
  SparseMatrix K, M;
  lap.interior(K, M);
  EigenSolver solver;
  EigenOptions o;
  o.count = 6;
  o.vectors = true;
  EigenResult r;
  const Status st = solver.solve(K, M, o, r);
  ASSERT_TRUE(st.is_ok()) << st.describe();
  ASSERT_EQ(r.pairs.size(), 6u);
  EXPECT_EQ(r.factorisations, 1);
  EXPECT_EQ(r.infinite_discarded, 0);
  double worst = 0, worst_residual = 0;
  for (int j = 0; j < 6; ++j) {
    const auto& p = r.pairs[j];
    worst = std::max(worst, std::abs(p.value - lap.sigma(j + 1)) / lap.sigma(j + 1));
    EXPECT_EQ(p.value.imag(), 0.0);
    EXPECT_TRUE(p.accurate);
    worst_residual = std::max(worst_residual, p.residual);
    EXPECT_LT(relative_residual(K, M, p.value, p.vector), 1e-10);
    EXPECT_NEAR(p.vector.norm(), 1.0, 1e-14);
  }
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_residual, o.residual_tolerance);
  RecordProperty("max_relative_error", std::to_string(worst));
  std::printf("  smallest 6 of 99: max relative error %.2e, max residual %.2e, %d restarts, %ld solves, %.3f s\n",
              worst, worst_residual, r.restarts, r.solves, r.seconds);
}

// Boundary nodes kept as unknowns with Dirichlet rows (identity in J, zero in B). With
// keep_columns = false J also drops the boundary columns of the interior rows (symmetric
// elimination) while B keeps them: B's pattern is then not a subset of J's.
class DirichletRows : public ::testing::TestWithParam<bool> {};

TEST_P(DirichletRows, SameFiniteSpectrumNoInfiniteOne) {
  const bool keep_columns = GetParam();
  const Laplacian1D lap(60);
  const int n = lap.elements + 1;
  auto boundary = [&](int i) { return i == 0 || i == lap.elements; };
  Triplets j, b;
  for (const auto& t : lap.stiffness)
    if (!boundary(t.row()) && (keep_columns || !boundary(t.col()))) j.push_back(t);
  for (const auto& t : lap.mass)
    if (!boundary(t.row())) b.push_back(t);
  j.emplace_back(0, 0, 1.0);
  j.emplace_back(n - 1, n - 1, 1.0);
  const SparseMatrix J = from_triplets(n, n, j), B = from_triplets(n, n, b);

  EigenSolver solver;
  EigenOptions o;
  o.count = 8;
  o.vectors = true;
  EigenResult r;
  const Status st = solver.solve(J, B, o, r);
  ASSERT_TRUE(st.is_ok()) << st.describe();
  ASSERT_EQ(r.pairs.size(), 8u);
  double worst = 0, worst_residual = 0, worst_boundary = 0;
  for (int k = 0; k < 8; ++k) {
    const auto& p = r.pairs[k];
    ASSERT_LT(std::abs(p.value), 2 * lap.sigma(8));  // bounded: no infinite eigenvalue slipped in
    worst = std::max(worst, std::abs(p.value - lap.sigma(k + 1)) / lap.sigma(k + 1));
    worst_residual = std::max(worst_residual, p.residual);
    worst_boundary = std::max({worst_boundary, std::abs(p.vector[0]), std::abs(p.vector[n - 1])});
  }
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_residual, 1e-10);
  EXPECT_LT(worst_boundary, 1e-12);  // phi = 0 on the Dirichlet nodes
  std::printf("  keep_columns %d: max relative error %.2e, max residual %.2e, boundary |phi| %.1e\n", keep_columns,
              worst, worst_residual, worst_boundary);
}

INSTANTIATE_TEST_SUITE_P(EigenSolver, DirichletRows, ::testing::Bool());

// Saddle point: K u + c p = sigma M u, c^T u = 0, with c = M phi_1 (phi_1 = sin(pi x) at the
// interior nodes, the first discrete eigenvector). The constraint removes exactly sigma_1: the
// finite spectrum is sigma_2, sigma_3, ... The multiplier row and column of B are zero and the
// infinite eigenvalue has index 2 (the case the purification of the vectors is for).
TEST(EigenSolver, LagrangeMultiplierRemovesFirstMode) {
  const Laplacian1D lap(80);
  SparseMatrix K, M;
  lap.interior(K, M);
  const int m = lap.elements - 1, n = m + 1;
  Vector phi1(m);
  for (int i = 0; i < m; ++i) phi1[i] = std::sin(std::numbers::pi * (i + 1) * lap.h);
  Vector c = M * phi1;
  c /= c.norm();
  Triplets j, b;
  for (int col = 0; col < m; ++col) {
    for (SparseMatrix::InnerIterator it(K, col); it; ++it) j.emplace_back(it.row(), col, it.value());
    for (SparseMatrix::InnerIterator it(M, col); it; ++it) b.emplace_back(it.row(), col, it.value());
    j.emplace_back(col, m, c[col]);
    j.emplace_back(m, col, c[col]);
  }
  const SparseMatrix J = from_triplets(n, n, j), B = from_triplets(n, n, b);

  EigenSolver solver;
  EigenOptions o;
  o.count = 6;
  o.vectors = true;
  EigenResult r;
  const Status st = solver.solve(J, B, o, r);
  ASSERT_TRUE(st.is_ok()) << st.describe();
  ASSERT_EQ(r.pairs.size(), 6u);
  double worst = 0, worst_residual = 0, worst_constraint = 0;
  for (int k = 0; k < 6; ++k) {
    const auto& p = r.pairs[k];
    ASSERT_LT(std::abs(p.value), 2 * lap.sigma(7));
    worst = std::max(worst, std::abs(p.value - lap.sigma(k + 2)) / lap.sigma(k + 2));
    worst_residual = std::max(worst_residual, p.residual);
    worst_constraint = std::max(worst_constraint, std::abs(c.cast<Complex>().dot(p.vector.head(m))));
  }
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_residual, 1e-10);
  EXPECT_LT(worst_constraint, 1e-12);
  std::printf("  max relative error %.2e, max residual %.2e, |c.u| %.1e\n", worst, worst_residual, worst_constraint);
}

// B of rank 5 (30 unknowns): asking for 8 eigenvalues finds the 5 finite ones (a dense reference:
// the eigenvalues of the Schur complement on the differential unknowns) and never reports one of
// the infinite ones.
TEST(EigenSolver, MoreWantedThanFiniteEigenvalues) {
  const int n = 30, d = 5;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  Triplets j, b;
  for (int i = 0; i < n; ++i) {
    j.emplace_back(i, i, (i < d ? 1.0 + i : 6.0) + 0.3 * U(rng));
    for (int k = 0; k < n; ++k)
      if (k != i && std::abs(U(rng)) < 0.15) j.emplace_back(i, k, U(rng));
    if (i < d) b.emplace_back(i, i, 1.0);
  }
  const SparseMatrix J = from_triplets(n, n, j), B = from_triplets(n, n, b);
  const Eigen::MatrixXd Jd(J);
  const Eigen::MatrixXd S =
      Jd.topLeftCorner(d, d) -
      Jd.topRightCorner(d, n - d) * Jd.bottomRightCorner(n - d, n - d).lu().solve(Jd.bottomLeftCorner(n - d, d));
  const Eigen::VectorXcd reference = S.eigenvalues();
  std::vector<Complex> expected(reference.data(), reference.data() + d);

  EigenSolver solver;
  EigenOptions o;
  o.count = 8;
  EigenResult r;
  const Status st = solver.solve(J, B, o, r);
  EXPECT_LE(r.pairs.size(), static_cast<size_t>(d));
  for (const auto& p : r.pairs) ASSERT_LT(std::abs(p.value), 1e3) << "an infinite eigenvalue reported as finite";
  ASSERT_TRUE(st.is_ok()) << st.describe();
  ASSERT_EQ(r.pairs.size(), static_cast<size_t>(d));
  const double err = match_error(r, expected);
  EXPECT_LT(err, 1e-10);
  EXPECT_GE(r.infinite_discarded, 1);
  std::printf("  %zu finite found, %d infinite discarded of %d converged, max relative error %.2e\n", r.pairs.size(),
              r.infinite_discarded, r.converged, err);
}

TEST(EigenSolver, RealShiftBetweenEigenvalues) {
  const Laplacian1D lap(100);
  SparseMatrix K, M;
  lap.interior(K, M);
  std::vector<Complex> all;
  for (int j = 1; j < lap.elements; ++j) all.emplace_back(lap.sigma(j));
  EigenSolver solver;
  EigenOptions o;
  o.shift = 0.5 * (lap.sigma(3) + lap.sigma(4));
  for (int count : {2, 4}) {
    o.count = count;
    EigenResult r;
    const Status st = solver.solve(K, M, o, r);
    ASSERT_TRUE(st.is_ok()) << st.describe();
    ASSERT_EQ(r.pairs.size(), static_cast<size_t>(count));
    const double err = match_error(r, nearest(all, o.shift, count));
    EXPECT_LT(err, 1e-10);
    for (const auto& p : r.pairs) EXPECT_LT(p.residual, 1e-10);
    std::printf("  s = %.6g, count %d: max relative error %.2e, first %.10g\n", o.shift.real(), count, err,
                r.pairs[0].value.real());
  }
}

// Complex shift near one eigenvalue of a complex spectrum with algebraic unknowns: complex
// arithmetic (znaupd, complex LU) finds the eigenvalues nearest s, not their conjugates.
TEST(EigenSolver, ComplexShiftFindsNearestComplexEigenvalues) {
  const RotationBlocks sys(30, 10);
  EigenSolver solver;
  EigenOptions o;
  o.count = 3;
  o.shift = Complex(0.6, 2.3);  // near 0.5 + 2.4i (block 7)
  o.vectors = true;
  EigenResult r;
  const Status st = solver.solve(sys.J, sys.B, o, r);
  ASSERT_TRUE(st.is_ok()) << st.describe();
  ASSERT_EQ(r.pairs.size(), 3u);
  const double err = match_error(r, nearest(sys.spectrum, o.shift, 3));
  EXPECT_LT(err, 1e-10);
  double worst_residual = 0;
  for (const auto& p : r.pairs) {
    EXPECT_GT(p.value.imag(), 0.0);
    worst_residual = std::max(worst_residual, relative_residual(sys.J, sys.B, p.value, p.vector));
  }
  EXPECT_LT(worst_residual, 1e-10);
  EXPECT_EQ(r.factorisations, 1);
  std::printf("  max relative error %.2e, max residual %.2e\n", err, worst_residual);
}

// Real shift on the same complex spectrum: the real solver returns conjugate pairs whose
// vectors, unpacked from dneupd's (real part, imaginary part) columns, are conjugate and satisfy
// J phi = sigma B phi (a wrong unpacking, e.g. the vector of sigma given to conj(sigma), fails).
TEST(EigenSolver, RealShiftConjugatePairsWithComplexVectors) {
  const RotationBlocks sys(30, 10);
  EigenSolver solver;
  EigenOptions o;
  o.count = 4;
  o.shift = 0.4;
  o.vectors = true;
  EigenResult r;
  const Status st = solver.solve(sys.J, sys.B, o, r);
  ASSERT_TRUE(st.is_ok()) << st.describe();
  ASSERT_EQ(r.pairs.size(), 4u);
  const double err = match_error(r, nearest(sys.spectrum, o.shift, 4));
  EXPECT_LT(err, 1e-10);
  double worst_residual = 0;
  for (size_t k = 0; k < r.pairs.size(); k += 2) {
    const auto& lower = r.pairs[k];  // sorted: negative imaginary part first within a pair
    const auto& upper = r.pairs[k + 1];
    EXPECT_LT(std::abs(lower.value - std::conj(upper.value)), 1e-14 * std::abs(upper.value));
    EXPECT_LT(lower.value.imag(), 0.0);
    EXPECT_LT((lower.vector - upper.vector.conjugate()).norm(), 1e-14);
    EXPECT_GT(upper.vector.imag().norm(), 0.1);     // genuinely complex
    EXPECT_GT(upper.vector.tail(10).norm(), 1e-3);  // the algebraic unknowns take part
    for (const auto* p : {&lower, &upper})
      worst_residual = std::max(worst_residual, relative_residual(sys.J, sys.B, p->value, p->vector));
  }
  EXPECT_LT(worst_residual, 1e-10);
  std::printf("  max relative error %.2e, max residual %.2e\n", err, worst_residual);
}
