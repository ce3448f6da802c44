// The shift-invert eigen-solver of stability/ as a solver: reuse of J's LU, bad input and
// non-convergence as statuses, the order of a spectrum, warm starts (the known spectra themselves:
// tests/unit/EigenSolverTest.cpp). Tolerances as there: ARPACK's 1e-12 on nu = 1/(sigma - s), 1e-10 asked.
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

TEST(EigenSolver, ReusesFactorisationOfJ) {
  const Laplacian1D lap(100);
  SparseMatrix K, M;
  lap.interior(K, M);
  EigenOptions o;
  o.count = 5;
  o.vectors = true;
  EigenSolver fresh_solver, reuse_solver;
  EigenResult fresh, reused;
  ASSERT_TRUE(fresh_solver.solve(K, M, o, fresh).is_ok());
  SparseLU lu;
  ASSERT_TRUE(lu.factorize(K).is_ok());
  const Status st = reuse_solver.solve(K, M, o, reused, &lu);
  ASSERT_TRUE(st.is_ok()) << st.describe();
  EXPECT_EQ(reused.factorisations, 0);
  EXPECT_EQ(fresh.factorisations, 1);
  EXPECT_EQ(lu.statistics().factorisations, 1);
  EXPECT_GT(lu.statistics().solves, 0);
  ASSERT_EQ(reused.pairs.size(), fresh.pairs.size());
  double worst = 0;
  for (size_t k = 0; k < fresh.pairs.size(); ++k) {
    worst = std::max(worst, std::abs(reused.pairs[k].value - fresh.pairs[k].value) / std::abs(fresh.pairs[k].value));
    EXPECT_LT((reused.pairs[k].vector - fresh.pairs[k].vector).norm(), 1e-10);
  }
  EXPECT_LT(worst, 1e-13);
  // a nonzero shift does not use it
  o.shift = 1.0;
  EigenResult shifted;
  ASSERT_TRUE(reuse_solver.solve(K, M, o, shifted, &lu).is_ok());
  EXPECT_EQ(shifted.factorisations, 1);
  std::printf("  reused vs fresh: max relative difference %.2e\n", worst);
}

TEST(EigenSolver, BadInputGivesStatus) {
  const int n = 10;
  Triplets t;
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, 1.0 + i);
  const SparseMatrix J = from_triplets(n, n, t), I = from_triplets(n, n, [] {
                                                   Triplets e;
                                                   for (int i = 0; i < 10; ++i) e.emplace_back(i, i, 1.0);
                                                   return e;
                                                 }());
  const SparseMatrix small = from_triplets(n - 1, n - 1, {});
  EigenSolver solver;
  EigenResult r;
  EigenOptions o;
  o.count = 3;

  Status st = solver.solve(J, small, o, r);
  EXPECT_EQ(st.code(), StatusCode::InvalidState) << st.describe();
  st = solver.solve(from_triplets(n, n - 1, {}), I, o, r);
  EXPECT_EQ(st.code(), StatusCode::InvalidState) << st.describe();
  for (int count : {0, n - 1, n}) {
    o.count = count;
    st = solver.solve(J, I, o, r);
    EXPECT_EQ(st.code(), StatusCode::InvalidState) << count << ": " << st.describe();
  }
  o.count = n - 2;  // the largest allowed
  st = solver.solve(J, I, o, r);
  EXPECT_TRUE(st.is_ok()) << st.describe();
  EXPECT_EQ(r.pairs.size(), static_cast<size_t>(n - 2));
  o.count = 3;
  o.ncv = 4;  // < count + 2
  st = solver.solve(J, I, o, r);
  EXPECT_EQ(st.code(), StatusCode::InvalidState) << st.describe();
  o.ncv = 0;
  o.shift = 3.0;  // an eigenvalue: J - s B is singular
  st = solver.solve(J, I, o, r);
  EXPECT_EQ(st.code(), StatusCode::SingularMatrix) << st.describe();
  o.shift = Complex(3.0, 0.5);  // fine in complex arithmetic
  st = solver.solve(J, I, o, r);
  EXPECT_TRUE(st.is_ok()) << st.describe();
  o.shift = 0.0;
  SparseLU unfactorised;
  st = solver.solve(J, I, o, r, &unfactorised);
  EXPECT_EQ(st.code(), StatusCode::InvalidState) << st.describe();
  SparseMatrix nan = J;
  nan.coeffRef(2, 2) = NAN;
  st = solver.solve(nan, I, o, r);
  EXPECT_EQ(st.code(), StatusCode::NotFinite) << st.describe();
  st = solver.solve(J, from_triplets(n, n, {}), o, r);  // B = 0: no finite eigenvalue
  EXPECT_FALSE(st.is_ok());
}

// A restart limit too low for the wanted accuracy: a NotConverged status with ARPACK's reason,
// and only converged pairs in the result.
TEST(EigenSolver, NonConvergenceIsAStatus) {
  const Laplacian1D lap(2000);
  SparseMatrix K, M;
  lap.interior(K, M);
  EigenSolver solver;
  EigenOptions o;
  o.count = 10;
  o.ncv = 12;
  o.max_restarts = 1;
  o.shift = 0.5 * (lap.sigma(200) + lap.sigma(201));  // deep inside a dense part of the spectrum
  EigenResult r;
  const Status st = solver.solve(K, M, o, r);
  EXPECT_EQ(st.code(), StatusCode::NotConverged) << st.describe();
  EXPECT_LT(static_cast<int>(r.pairs.size()), o.count);
  std::printf("  %s; %zu pairs returned\n", st.describe().c_str(), r.pairs.size());
}

// The order of a spectrum does not hang on the last bits of a real part: a conjugate pair whose
// real parts differ by rounding (computed apart) reads (x - i omega, x + i omega) whichever is
// above; values with clearly different real parts go by real part whatever their imaginary parts.
TEST(EigenSolver, ASpectrumIsOrderedByRealPartThenAConjugatePairByImaginaryPart) {
  const double x = 0.125, above = std::nextafter(x, 1.0), far = std::nextafter(above, 1.0) + 1e-9;
  auto pair = [](double re, double im) {
    EigenPair p;
    p.value = {re, im};
    return p;
  };
  std::vector<EigenPair> s = {pair(far, -5.0), pair(x, 2.0), pair(above, -2.0), pair(-1.0, 3.0)};
  order_spectrum(s);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].value, std::complex<double>(-1.0, 3.0));
  EXPECT_EQ(s[1].value.imag(), -2.0);
  EXPECT_EQ(s[2].value.imag(), 2.0);
  EXPECT_EQ(s[3].value, std::complex<double>(far, -5.0));
}

// Warm start (EigenOptions::start): the eigenvalues nearest the shift of a clustered spectrum
// (tridiagonal J with diagonal 1 + 2e-3 i and off-diagonal 1e-4, B = I, n = 400: the nu = 1/sigma
// of OP differ by 0.2% from one to the next, so cold Arnoldi needs many restarts), at a point
// moved from the first by a smooth change of the diagonal (2e-4 cos i). Started from the first
// point's eigenvectors, ARPACK finds the same eigenvalues (against a dense solver, to 1e-10) in
// fewer solves; started from unrelated vectors (those of the largest eigenvalues), the random part
// of the start still leads it to the right ones.
TEST(EigenSolver, AWarmStartFromANearbyPointsEigenvectorsFindsTheSameEigenvaluesInFewerSolves) {
  const int n = 400;
  auto clustered = [n](double wobble) {
    Triplets t;
    for (int i = 0; i < n; ++i) {
      t.emplace_back(i, i, 1.0 + 2e-3 * i + wobble * std::cos(i));
      if (i + 1 < n) {
        t.emplace_back(i, i + 1, -1e-4);
        t.emplace_back(i + 1, i, -1e-4);
      }
    }
    return from_triplets(n, n, t);
  };
  Triplets identity;
  for (int i = 0; i < n; ++i) identity.emplace_back(i, i, 1.0);
  const SparseMatrix B = from_triplets(n, n, identity), J0 = clustered(0.0), J1 = clustered(2e-4);
  const Eigen::MatrixXd J1_dense(J1);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(J1_dense);
  std::vector<Complex> exact;
  for (int i = 0; i < n; ++i) exact.emplace_back(dense.eigenvalues()[i], 0.0);

  EigenSolver solver;
  EigenOptions o;
  o.count = 6;
  o.vectors = true;
  EigenResult first, cold, warm, unrelated;
  ASSERT_TRUE(solver.solve(J0, B, o, first).is_ok());
  ASSERT_TRUE(solver.solve(J1, B, o, cold).is_ok());
  for (const auto& p : first.pairs) o.start.push_back(p.vector);
  ASSERT_TRUE(solver.solve(J1, B, o, warm).is_ok());
  o.start.clear();
  for (int i = n - 6; i < n; ++i) o.start.push_back(Eigen::VectorXcd(dense.eigenvectors().col(i).cast<Complex>()));
  ASSERT_TRUE(solver.solve(J1, B, o, unrelated).is_ok());

  const auto want = nearest(exact, 0.0, 6);
  EXPECT_LT(match_error(cold, want), 1e-10);
  EXPECT_LT(match_error(warm, want), 1e-10);
  EXPECT_LT(match_error(unrelated, want), 1e-10);
  EXPECT_LT(warm.solves, cold.solves);
  std::printf("  solves: cold %ld, warm %ld, from unrelated vectors %ld\n", cold.solves, warm.solves, unrelated.solves);
}
