// Shift-invert eigen-solver of stability/: known spectra of J phi = sigma B phi with regular and
// singular B, real and complex shifts, the unpacking of conjugate pairs, reuse of J's LU, bad input.
// Tolerances: ARPACK's tolerance 1e-12 bounds the relative error of the Ritz values nu = 1/(sigma - s)
// of the wanted (largest) nu, so sigma is good to about 1e-12 |sigma - s|; the tests ask 1e-10.
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

using namespace keller;
using Complex = std::complex<double>;
using Triplets = std::vector<Eigen::Triplet<double, int>>;

namespace {

SparseMatrix from_triplets(int rows, int cols, const Triplets& t) {
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

double relative_residual(const SparseMatrix& J, const SparseMatrix& B, Complex sigma, const Eigen::VectorXcd& phi) {
  const Eigen::MatrixXcd Jd = Eigen::MatrixXd(J).cast<Complex>(), Bd = Eigen::MatrixXd(B).cast<Complex>();
  return (Jd * phi - sigma * (Bd * phi)).norm() / ((Jd.norm() + std::abs(sigma) * Bd.norm()) * phi.norm());
}

// The `count` values of `all` nearest s.
std::vector<Complex> nearest(std::vector<Complex> all, Complex s, int count) {
  std::sort(all.begin(), all.end(), [s](Complex a, Complex b) { return std::abs(a - s) < std::abs(b - s); });
  all.resize(count);
  return all;
}

// Largest relative distance from each computed value to the nearest of `expected`, and whether
// every expected value is matched (a one-to-one check: the values are distinct).
double match_error(const EigenResult& r, const std::vector<Complex>& expected) {
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

}  // namespace

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
