// The sparse LU with each backend (UMFPACK, and MUMPS where keller is built with it): solutions
// against dense LU, the determinant's sign and size, status codes, refinement, reuse of the
// symbolic analysis, the choice of backend.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

#include "core/Scene.hpp"
#include "core/SparseLU.hpp"

using namespace keller;
using Backend = SparseLUOptions::Backend;

namespace {

SparseMatrix random_sparse(int n, double density, unsigned seed, bool singular = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0 + U(rng));
    for (int j = 0; j < n; ++j)
      if (j != i && std::abs(U(rng)) < density) t.emplace_back(i, j, U(rng));
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  if (singular) {  // last row = first row
    Eigen::MatrixXd D(A);
    D.row(n - 1) = D.row(0);
    A = D.sparseView(0.0, 0.0);
    for (int i = 0; i < n; ++i) A.coeffRef(i, i) += 0.0;
  }
  A.makeCompressed();
  return A;
}

// A row permutation P of a strictly row-diagonally dominant matrix D with diagonal entries of
// random signs: sign det(P D) = sign(P) prod sign(D_ii) exactly (D + t (D - diag D), t in [0, 1],
// stays dominant, so nonsingular, and det keeps its sign). P D has zeros on its diagonal where P
// moves rows: the backends must pivot off it and count the interchanges.
struct KnownSign {
  SparseMatrix A;
  int sign = 0;
};

KnownSign permuted_dominant(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<int> rows(static_cast<size_t>(n));
  std::iota(rows.begin(), rows.end(), 0);
  std::shuffle(rows.begin(), rows.end(), rng);
  // sign of the permutation: (-1)^(n - number of cycles)
  int parity = 0;
  std::vector<bool> seen(static_cast<size_t>(n), false);
  for (int i = 0; i < n; ++i) {
    if (seen[static_cast<size_t>(i)]) continue;
    int length = 0;
    for (int j = i; !seen[static_cast<size_t>(j)]; j = rows[static_cast<size_t>(j)], ++length)
      seen[static_cast<size_t>(j)] = true;
    parity += length - 1;
  }
  KnownSign out;
  out.sign = parity % 2 == 0 ? 1 : -1;
  std::vector<Eigen::Triplet<double, int>> t;
  constexpr double kOffDiagonalShare = 0.9;  // of the diagonal's size, spread over a row: still dominant
  constexpr int kOffDiagonalPerRow = 3;
  for (int i = 0; i < n; ++i) {
    const double d = (U(rng) < 0 ? -1.0 : 1.0) * (1.0 + std::abs(U(rng)));
    out.sign *= d > 0 ? 1 : -1;
    const int r = rows[static_cast<size_t>(i)];  // row i of D becomes row r of P D
    t.emplace_back(r, i, d);
    for (int k = 0; k < kOffDiagonalPerRow; ++k) {
      const int j = static_cast<int>((i + 1 + k * 7 + seed) % static_cast<unsigned>(n));
      if (j != i) t.emplace_back(r, j, U(rng) * kOffDiagonalShare * std::abs(d) / kOffDiagonalPerRow);
    }
  }
  out.A.resize(n, n);
  out.A.setFromTriplets(t.begin(), t.end());
  out.A.makeCompressed();
  return out;
}

SparseLUOptions with(Backend b) {
  SparseLUOptions o;
  o.backend = b;
  return o;
}

// Upwinded convection-diffusion on an m x m grid (5-point stencil, Dirichlet rows eliminated):
// unsymmetric, nonsingular, and a pattern like a finite-element Jacobian's.
SparseMatrix convection_diffusion(int m) {
  const int n = m * m;
  constexpr double kConvection = 0.7;  // cell Peclet number: upwinding keeps it an M-matrix
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const int k = i * m + j;
      t.emplace_back(k, k, 4.0 + kConvection);
      if (i > 0) t.emplace_back(k, k - m, -1.0 - kConvection);
      if (i + 1 < m) t.emplace_back(k, k + m, -1.0);
      if (j > 0) t.emplace_back(k, k - 1, -1.0);
      if (j + 1 < m) t.emplace_back(k, k + 1, -1.0);
    }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

Scene linear_solver_scene(const std::string& text) {
  SceneSchema schema;
  declare_linear_solver_keys(schema);
  return Scene::parse(text, "s.toml", schema);
}

// The message of the SceneError that reading the scene's linear solver options throws ("" if none).
std::string linear_solver_error(const std::string& text) {
  try {
    (void)sparse_lu_options_from(linear_solver_scene(text));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

// Each test runs once per backend; MUMPS's are skipped where keller is built without it.
class SparseLUBackend : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    if (GetParam() == Backend::Mumps && !mumps_available()) GTEST_SKIP() << "built without MUMPS";
  }
  SparseLUOptions options() const { return with(GetParam()); }
};

INSTANTIATE_TEST_SUITE_P(Backends, SparseLUBackend, ::testing::Values(Backend::Umfpack, Backend::Mumps),
                         [](const auto& p) { return std::string(to_string(p.param)); });

}  // namespace

// The factorisation reports the backend that made it: a test below that passes for the wrong one
// would otherwise go unnoticed.
TEST_P(SparseLUBackend, SaysWhichBackendFactorised) {
  SparseLU lu(options());
  ASSERT_TRUE(lu.factorize(random_sparse(20, 0.1, 7)).is_ok());
  EXPECT_EQ(lu.statistics().backend, to_string(GetParam()));
}

TEST_P(SparseLUBackend, SolvesLikeDenseLU) {
  const SparseMatrix A = random_sparse(60, 0.08, 1);
  const Vector b = Vector::LinSpaced(60, -1, 2);
  SparseLU lu(options());
  ASSERT_TRUE(lu.factorize(A).is_ok());
  Vector x, xt;
  ASSERT_TRUE(lu.solve(b, x).is_ok());
  ASSERT_TRUE(lu.solve(b, xt, true).is_ok());
  const Eigen::MatrixXd D(A);
  EXPECT_LT((x - D.partialPivLu().solve(b)).norm() / x.norm(), 1e-13);
  EXPECT_LT((xt - D.transpose().partialPivLu().solve(b)).norm() / xt.norm(), 1e-13);
  EXPECT_EQ(lu.determinant_sign(), D.determinant() > 0 ? 1 : -1);
  EXPECT_NEAR(lu.log_abs_determinant(), std::log(std::abs(D.determinant())), 1e-10);
  const SparseLU::Statistics& s = lu.statistics();
  EXPECT_GE(s.nnz_lu, A.nonZeros());
  EXPECT_GT(s.flops, 0);
  EXPECT_GT(s.peak_memory_bytes, 0);
  EXPECT_FALSE(s.ordering_used.empty());
}

// Several columns at once (solve_columns: MUMPS in one pass over its factors) give each column's
// plain solve, with A and A^T, to rounding (1e-13 relative against dense LU), and an empty block
// is no work.
TEST_P(SparseLUBackend, SolvesSeveralColumnsLikeOneAtATime) {
  const SparseMatrix A = random_sparse(60, 0.08, 3);
  Eigen::MatrixXd b(60, 3);
  b.col(0) = Vector::LinSpaced(60, -1, 2);
  b.col(1) = Vector::Ones(60);
  b.col(2) = Vector::LinSpaced(60, 3, -2).array().sin();
  SparseLU lu(options());
  ASSERT_TRUE(lu.factorize(A).is_ok());
  const Eigen::MatrixXd D(A);
  for (bool transpose : {false, true}) {
    Eigen::MatrixXd x;
    const long before = lu.statistics().solves;
    ASSERT_TRUE(lu.solve_columns(b, x, transpose).is_ok());
    EXPECT_EQ(lu.statistics().solves - before, 3);
    const Eigen::MatrixXd expected =
        transpose ? Eigen::MatrixXd(D.transpose().partialPivLu().solve(b)) : Eigen::MatrixXd(D.partialPivLu().solve(b));
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT((x.col(k) - expected.col(k)).norm() / expected.col(k).norm(), 1e-13) << k << transpose;
      Vector one;
      ASSERT_TRUE(lu.solve(b.col(k), one, transpose, 0).is_ok());
      EXPECT_LT((x.col(k) - one).norm() / one.norm(), 1e-13) << k << transpose;
    }
  }
  Eigen::MatrixXd none;
  ASSERT_TRUE(lu.solve_columns(Eigen::MatrixXd(60, 0), none).is_ok());
  EXPECT_EQ(none.cols(), 0);
}

// The continuation reads branch points and folds off the determinant's sign: on 200 matrices of
// sizes 2 to 60 whose sign is known by construction (and needs row interchanges), both
// backends give it, and log|det| agrees with dense LU to rounding (1e-10 absolute in a
// log of size up to about 40).
TEST_P(SparseLUBackend, DeterminantSignOfPermutedMatricesIsExact) {
  constexpr int kMatrices = 200;
  int positive = 0;
  for (int k = 0; k < kMatrices; ++k) {
    const int n = 2 + k % 59;
    const KnownSign m = permuted_dominant(n, static_cast<unsigned>(k));
    SparseLU lu(options());
    ASSERT_TRUE(lu.factorize(m.A).is_ok()) << "matrix " << k;
    ASSERT_EQ(lu.determinant_sign(), m.sign) << "matrix " << k << ", n = " << n;
    const Eigen::MatrixXd D(m.A);
    ASSERT_EQ(D.determinant() > 0 ? 1 : -1, m.sign) << "the construction, matrix " << k;
    EXPECT_NEAR(lu.log_abs_determinant(), std::log(std::abs(D.determinant())), 1e-10) << "matrix " << k;
    positive += m.sign > 0;
  }
  // both signs occur often (a fair sample, not a constant answer)
  EXPECT_GT(positive, kMatrices / 4);
  EXPECT_LT(positive, 3 * kMatrices / 4);
}

TEST_P(SparseLUBackend, AnalysesOncePerPattern) {
  SparseMatrix A = random_sparse(40, 0.1, 2);
  SparseLU lu(options());
  for (int k = 0; k < 3; ++k) {
    A.coeffs() *= 1.5;
    ASSERT_TRUE(lu.factorize(A).is_ok());
  }
  EXPECT_EQ(lu.statistics().analyses, 1);
  EXPECT_EQ(lu.statistics().factorisations, 3);
  const SparseMatrix B = random_sparse(40, 0.1, 3);  // another pattern: analysed again
  ASSERT_TRUE(lu.factorize(B).is_ok());
  EXPECT_EQ(lu.statistics().analyses, 2);
  EXPECT_GT(lu.statistics().nnz_lu, 0);
}

// A second SparseLU with the same pattern and controls takes the last symbolic analysis instead
// of repeating it (a run factorises J from several places), and solves its own values exactly;
// other controls (ordering) or another pattern get their own analysis.
TEST_P(SparseLUBackend, SymbolicAnalysisSharedBetweenObjects) {
  const SparseMatrix A = random_sparse(50, 0.1, 11);
  SparseMatrix A2 = A;
  A2.coeffs() = A2.coeffs().array() * Vector::LinSpaced(A2.nonZeros(), 0.5, 1.5).array();
  const Vector b = Vector::LinSpaced(50, -1, 2);
  SparseLU first(options()), second(options());
  ASSERT_TRUE(first.factorize(A).is_ok());
  EXPECT_EQ(first.statistics().analyses, 1);
  ASSERT_TRUE(second.factorize(A2).is_ok());
  EXPECT_EQ(second.statistics().analyses, 0);
  EXPECT_EQ(second.statistics().analyses_reused, 1);
  EXPECT_EQ(second.statistics().ordering_used, first.statistics().ordering_used);
  Vector x;
  ASSERT_TRUE(second.solve(b, x).is_ok());
  EXPECT_LT((A2 * x - b).norm() / b.norm(), 1e-13);
  // the first object still solves with its own factorisation
  ASSERT_TRUE(first.solve(b, x).is_ok());
  EXPECT_LT((A * x - b).norm() / b.norm(), 1e-13);
  SparseLUOptions metis = options();
  metis.ordering = SparseLUOptions::Ordering::Metis;
  SparseLU third(metis);
  ASSERT_TRUE(third.factorize(A).is_ok());
  EXPECT_EQ(third.statistics().analyses, 1);
  EXPECT_EQ(third.statistics().analyses_reused, 0);
}

TEST_P(SparseLUBackend, SingularMatrixIsAStatusNotACrash) {
  const SparseMatrix A = random_sparse(30, 0.1, 4, true);
  SparseLU lu(options());
  const Status st = lu.factorize(A);
  EXPECT_EQ(st.code(), StatusCode::SingularMatrix) << st.describe();
  EXPECT_FALSE(lu.factorized());
  EXPECT_THROW(
      {
        Vector x;
        (void)lu.solve(Vector::Ones(30), x);
      },
      std::logic_error);
  // the same object factorises a regular matrix of the same pattern afterwards
  SparseMatrix B = A;
  B.coeffRef(29, 29) += 1.0;
  EXPECT_TRUE(lu.factorize(B).is_ok());
}

TEST_P(SparseLUBackend, OrderingsAgree) {
  const SparseMatrix A = random_sparse(80, 0.05, 5);
  const Vector b = Vector::Ones(80);
  std::vector<SparseLUOptions::Ordering> orderings = {SparseLUOptions::Ordering::Amd, SparseLUOptions::Ordering::Metis,
                                                      SparseLUOptions::Ordering::Best};
  if (GetParam() == Backend::Umfpack) orderings.push_back(SparseLUOptions::Ordering::Cholmod);
  Vector ref;
  for (auto o : orderings) {
    SparseLUOptions opt = options();
    opt.ordering = o;
    SparseLU lu(opt);
    ASSERT_TRUE(lu.factorize(A).is_ok()) << to_string(o);
    Vector x;
    ASSERT_TRUE(lu.solve(b, x).is_ok());
    if (ref.size() == 0) ref = x;
    EXPECT_LT((x - ref).norm() / ref.norm(), 1e-12) << to_string(o);
  }
}

namespace {
// zero_diagonal with shift added to its diagonal factorised (the analysis plans its pivots on the
// diagonal), then zero_diagonal itself on that same analysis.
void factorise_on_a_dominant_analysis(SparseLU& lu, const SparseMatrix& zero_diagonal, double shift) {
  SparseMatrix dominant = zero_diagonal;
  for (int i = 0; i < dominant.rows(); ++i) dominant.coeffRef(i, i) += shift;
  ASSERT_TRUE(lu.factorize(dominant).is_ok());
  const Status st = lu.factorize(zero_diagonal);
  ASSERT_TRUE(st.is_ok()) << st.describe();
  EXPECT_EQ(lu.statistics().analyses, 1);
}
}  // namespace

// A pattern analysed on values with a dominant diagonal, then factorised with values whose
// diagonal is zero wherever the permutation of permuted_dominant moves a row: the pivots the
// analysis planned are zero, and the numeric factorisation has to pivot elsewhere (UMFPACK: rows
// of its frontal matrices; MUMPS: delayed pivots) on the reused analysis. The solution matches
// dense LU and the determinant's sign is the known one.
TEST_P(SparseLUBackend, PivotsOffAZeroDiagonalOnAReusedAnalysis) {
  constexpr int kN = 40;
  const KnownSign m = permuted_dominant(kN, 17);
  std::vector<Eigen::Triplet<double, int>> t;
  for (int j = 0; j < kN; ++j)
    for (SparseMatrix::InnerIterator it(m.A, j); it; ++it) t.emplace_back(it.row(), j, it.value());
  for (int i = 0; i < kN; ++i) t.emplace_back(i, i, 0.0);  // the diagonal in the pattern
  SparseMatrix zero_diagonal(kN, kN);
  zero_diagonal.setFromTriplets(t.begin(), t.end());
  zero_diagonal.makeCompressed();
  int zero_pivots = 0;
  for (int i = 0; i < kN; ++i) zero_pivots += zero_diagonal.coeff(i, i) == 0.0;
  ASSERT_GT(zero_pivots, kN / 2) << "the construction: most planned pivots are zero";
  SparseLU lu(options());
  ASSERT_NO_FATAL_FAILURE(factorise_on_a_dominant_analysis(lu, zero_diagonal, 10.0 * kN));
  const Eigen::MatrixXd D(zero_diagonal);
  const Vector b = Vector::LinSpaced(kN, -1, 2);
  Vector x, xt;
  ASSERT_TRUE(lu.solve(b, x).is_ok());
  ASSERT_TRUE(lu.solve(b, xt, true).is_ok());
  EXPECT_LT((x - D.partialPivLu().solve(b)).norm() / x.norm(), 1e-13);
  EXPECT_LT((xt - D.transpose().partialPivLu().solve(b)).norm() / xt.norm(), 1e-13);
  EXPECT_EQ(lu.determinant_sign(), m.sign);
  EXPECT_NEAR(lu.log_abs_determinant(), std::log(std::abs(D.determinant())), 1e-10);
}

// Pivoting the analysis did not plan, on a 2D pattern (a 30 x 30 grid, five points, random
// off-diagonal values): analysed with a dominant diagonal, factorised with a zero one, so that
// every planned pivot is zero and is delayed up the elimination tree. MUMPS's fronts then outgrow
// the workspace its analysis estimated (INFO(1) = -9, twice here), which keller provides and grows
// until the factorisation fits; the solution matches dense LU.
TEST_P(SparseLUBackend, PivotsBeyondTheAnalysisWorkspaceEstimate) {
  constexpr int kGrid = 30, kN = kGrid * kGrid;
  std::vector<Eigen::Triplet<double, int>> t;
  unsigned seed = 12345;
  auto value = [&]() {
    seed = seed * 1103515245u + 12345u;
    return static_cast<double>((seed >> 8) % 1000) / 500.0 - 1.0;
  };
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const int r = i * kGrid + j;
      t.emplace_back(r, r, 0.0);
      if (i > 0) t.emplace_back(r, r - kGrid, value());
      if (i < kGrid - 1) t.emplace_back(r, r + kGrid, value());
      if (j > 0) t.emplace_back(r, r - 1, value());
      if (j < kGrid - 1) t.emplace_back(r, r + 1, value());
    }
  SparseMatrix zero_diagonal(kN, kN);
  zero_diagonal.setFromTriplets(t.begin(), t.end());
  zero_diagonal.makeCompressed();
  SparseLU lu(options());
  ASSERT_NO_FATAL_FAILURE(factorise_on_a_dominant_analysis(lu, zero_diagonal, 10.0));
  const Eigen::MatrixXd D(zero_diagonal);
  const Vector b = Vector::LinSpaced(kN, -1, 2);
  Vector x;
  ASSERT_TRUE(lu.solve(b, x).is_ok());
  const Eigen::PartialPivLU<Eigen::MatrixXd> dense(D);
  EXPECT_LT((x - dense.solve(b)).norm() / x.norm(), 1e-10);
  EXPECT_EQ(lu.determinant_sign(), dense.determinant() > 0 ? 1 : -1);
}

// A matrix without a single entry in one column is singular by its pattern alone (MUMPS finds
// it in the analysis, UMFPACK in the factorisation): a status as for a numerically singular one.
TEST_P(SparseLUBackend, StructurallySingularMatrixIsAStatus) {
  SparseMatrix A = random_sparse(30, 0.1, 6);
  A.prune([](int, int col, double) { return col != 12; });
  A.makeCompressed();
  SparseLU lu(options());
  const Status st = lu.factorize(A);
  EXPECT_EQ(st.code(), StatusCode::SingularMatrix) << st.describe();
  EXPECT_FALSE(lu.factorized());
}

// The two backends on the same matrix: the same solutions (A x = b and A^T x = b) and the same
// determinant. cond(A) is computed, and the solutions may differ by the forward error bound of
// two backward-stable solves, 2 cond(A) eps, with a factor 10 for the constants of the bound.
TEST(SparseLUBackendsAgree, SameSolutionsAndDeterminant) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  const SparseMatrix A = convection_diffusion(15);
  const Eigen::MatrixXd D(A);
  const Eigen::VectorXd sv = D.bdcSvd().singularValues();
  const double cond = sv(0) / sv(sv.size() - 1);
  const double bound = 10 * 2 * cond * std::numeric_limits<double>::epsilon();
  const Vector b = Vector::LinSpaced(A.rows(), -1, 2);
  SparseLU umfpack(with(Backend::Umfpack)), mumps(with(Backend::Mumps));
  ASSERT_TRUE(umfpack.factorize(A).is_ok());
  ASSERT_TRUE(mumps.factorize(A).is_ok());
  for (bool transpose : {false, true}) {
    Vector xu, xm;
    ASSERT_TRUE(umfpack.solve(b, xu, transpose).is_ok());
    ASSERT_TRUE(mumps.solve(b, xm, transpose).is_ok());
    EXPECT_LT((xu - xm).norm() / xu.norm(), bound) << "transpose " << transpose << ", cond " << cond;
  }
  EXPECT_EQ(umfpack.determinant_sign(), mumps.determinant_sign());
  // log|det| = sum of the logs of the pivots, about 330 here; each backend within rounding of it
  EXPECT_NEAR(umfpack.log_abs_determinant(), mumps.log_abs_determinant(), 1e-10);
  const Eigen::PartialPivLU<Eigen::MatrixXd> dense(D);
  double log_abs = 0;
  for (int i = 0; i < D.rows(); ++i) log_abs += std::log(std::abs(dense.matrixLU()(i, i)));
  EXPECT_NEAR(mumps.log_abs_determinant(), log_abs, 1e-10);
}

// auto is MUMPS where keller is built with it, UMFPACK where not or where an option only UMFPACK
// has is set; MUMPS asked for where it cannot do the job is an error naming the key.
TEST(SparseLUBackendChoice, AutoIsMumpsWhereBuiltWithItElseUmfpack) {
  SparseLUOptions o;
  EXPECT_EQ(o.backend, Backend::Auto);
  EXPECT_EQ(resolved_backend(o), mumps_available() ? Backend::Mumps : Backend::Umfpack);
  SparseLU lu(o);
  ASSERT_TRUE(lu.factorize(random_sparse(10, 0.2, 3)).is_ok());
  EXPECT_EQ(lu.statistics().backend, mumps_available() ? "mumps" : "umfpack");
  o.strategy = SparseLUOptions::Strategy::Symmetric;
  EXPECT_EQ(resolved_backend(o), Backend::Umfpack);
  o.strategy = SparseLUOptions::Strategy::Auto;
  o.ordering = SparseLUOptions::Ordering::Cholmod;
  EXPECT_EQ(resolved_backend(o), Backend::Umfpack);
}

TEST(SparseLUBackendChoice, MumpsWhereItCannotDoTheJobIsAnErrorNamingTheKey) {
  SparseLUOptions o;
  o.backend = Backend::Mumps;
  o.strategy = SparseLUOptions::Strategy::Unsymmetric;
  try {
    SparseLU lu(o);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(mumps_available() ? "linear_solver.strategy" : "linear_solver.backend"), std::string::npos)
        << what;
  }
}

// [linear_solver] backend: an unknown value is an error naming the key and the choices; MUMPS
// with an option only UMFPACK has (or in a build without MUMPS) is an error naming the key, where
// it is set, and the option; umfpack takes every option.
TEST(SparseLUBackendChoice, SceneKeyIsValidated) {
  EXPECT_EQ(sparse_lu_options_from(linear_solver_scene("")).backend, Backend::Auto);
  try {
    (void)linear_solver_scene("[linear_solver]\nbackend = \"pardiso\"\n");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("linear_solver.backend"), std::string::npos) << what;
    EXPECT_NE(what.find("umfpack"), std::string::npos) << what;
  }
  const SparseLUOptions umfpack =
      sparse_lu_options_from(linear_solver_scene("[linear_solver]\nbackend = \"umfpack\"\nstrategy = \"symmetric\"\n"));
  EXPECT_EQ(umfpack.backend, Backend::Umfpack);
  EXPECT_EQ(umfpack.strategy, SparseLUOptions::Strategy::Symmetric);
  const std::string symmetric = linear_solver_error("[linear_solver]\nbackend = \"mumps\"\nstrategy = \"symmetric\"\n");
  EXPECT_NE(symmetric.find("s.toml:2"), std::string::npos) << symmetric;  // the line of backend
  EXPECT_NE(symmetric.find("linear_solver.backend"), std::string::npos) << symmetric;
  EXPECT_NE(symmetric.find(mumps_available() ? "linear_solver.strategy = \"symmetric\"" : "without MUMPS"),
            std::string::npos)
      << symmetric;
  const std::string cholmod = linear_solver_error("[linear_solver]\nbackend = \"mumps\"\nordering = \"cholmod\"\n");
  EXPECT_NE(cholmod.find(mumps_available() ? "linear_solver.ordering = \"cholmod\"" : "without MUMPS"),
            std::string::npos)
      << cholmod;
  EXPECT_EQ(linear_solver_error("[linear_solver]\nbackend = \"mumps\"\nordering = \"best\"\n").empty(),
            mumps_available());
}
