// UMFPACK wrapper: solutions against dense LU, status codes, reuse of the symbolic analysis.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "core/SparseLU.hpp"

using namespace keller;

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
}  // namespace

TEST(SparseLU, SolvesLikeDenseLU) {
  const SparseMatrix A = random_sparse(60, 0.08, 1);
  const Vector b = Vector::LinSpaced(60, -1, 2);
  SparseLU lu;
  ASSERT_TRUE(lu.factorize(A).is_ok());
  Vector x, xt;
  ASSERT_TRUE(lu.solve(b, x).is_ok());
  ASSERT_TRUE(lu.solve(b, xt, true).is_ok());
  const Eigen::MatrixXd D(A);
  EXPECT_LT((x - D.partialPivLu().solve(b)).norm() / x.norm(), 1e-13);
  EXPECT_LT((xt - D.transpose().partialPivLu().solve(b)).norm() / xt.norm(), 1e-13);
  EXPECT_EQ(lu.determinant_sign(), D.determinant() > 0 ? 1 : -1);
  EXPECT_NEAR(lu.log_abs_determinant(), std::log(std::abs(D.determinant())), 1e-10);
}

TEST(SparseLU, AnalysesOncePerPattern) {
  SparseMatrix A = random_sparse(40, 0.1, 2);
  SparseLU lu;
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
TEST(SparseLU, SymbolicAnalysisSharedBetweenObjects) {
  const SparseMatrix A = random_sparse(50, 0.1, 11);
  SparseMatrix A2 = A;
  A2.coeffs() = A2.coeffs().array() * Vector::LinSpaced(A2.nonZeros(), 0.5, 1.5).array();
  const Vector b = Vector::LinSpaced(50, -1, 2);
  SparseLU first, second;
  ASSERT_TRUE(first.factorize(A).is_ok());
  EXPECT_EQ(first.statistics().analyses, 1);
  ASSERT_TRUE(second.factorize(A2).is_ok());
  EXPECT_EQ(second.statistics().analyses, 0);
  EXPECT_EQ(second.statistics().analyses_reused, 1);
  Vector x;
  ASSERT_TRUE(second.solve(b, x).is_ok());
  EXPECT_LT((A2 * x - b).norm() / b.norm(), 1e-13);
  // the first object still solves with its own factorisation
  ASSERT_TRUE(first.solve(b, x).is_ok());
  EXPECT_LT((A * x - b).norm() / b.norm(), 1e-13);
  SparseLUOptions metis;
  metis.ordering = SparseLUOptions::Ordering::Metis;
  SparseLU third(metis);
  ASSERT_TRUE(third.factorize(A).is_ok());
  EXPECT_EQ(third.statistics().analyses, 1);
  EXPECT_EQ(third.statistics().analyses_reused, 0);
}

TEST(SparseLU, SingularMatrixIsAStatusNotACrash) {
  const SparseMatrix A = random_sparse(30, 0.1, 4, true);
  SparseLU lu;
  const Status st = lu.factorize(A);
  EXPECT_EQ(st.code(), StatusCode::SingularMatrix);
  EXPECT_FALSE(lu.factorized());
}

TEST(SparseLU, OrderingsAgree) {
  const SparseMatrix A = random_sparse(80, 0.05, 5);
  const Vector b = Vector::Ones(80);
  Vector ref;
  for (auto o :
       {SparseLUOptions::Ordering::Amd, SparseLUOptions::Ordering::Metis, SparseLUOptions::Ordering::Cholmod}) {
    SparseLUOptions opt;
    opt.ordering = o;
    SparseLU lu(opt);
    ASSERT_TRUE(lu.factorize(A).is_ok()) << to_string(o);
    Vector x;
    ASSERT_TRUE(lu.solve(b, x).is_ok());
    if (ref.size() == 0) ref = x;
    EXPECT_LT((x - ref).norm() / ref.norm(), 1e-12) << to_string(o);
  }
}
