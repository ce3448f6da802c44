// The fill-reducing orderings keller computes (METIS's nested dissection, given to MUMPS) and how
// `best` chooses among MUMPS's candidates: the choice as a function on synthetic trials, the
// nested dissection's defining property (its last pivots separate the graph into balanced parts)
// on a grid, and `best` on two small patterns whose winners differ.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "core/FillOrdering.hpp"
#include "core/SparseLU.hpp"
#include "runs/bench/ModelGrid.hpp"

using namespace keller;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

SparseMatrix grid(int nx, int ny, bool nine_point = false, bool upper_only = false) {
  return bench::model_grid(nx, ny, nine_point, upper_only);
}

std::vector<int> order_of(const SparseMatrix& A) {
  return nested_dissection_order(static_cast<int>(A.rows()), A.outerIndexPtr(), A.innerIndexPtr());
}

// Sizes of the connected components of the grid's graph without the vertices `removed`.
std::vector<int> components(const SparseMatrix& A, const std::vector<bool>& removed) {
  const int n = static_cast<int>(A.rows());
  std::vector<int> label(static_cast<size_t>(n), -1), sizes, stack;
  for (int s = 0; s < n; ++s) {
    if (removed[static_cast<size_t>(s)] || label[static_cast<size_t>(s)] >= 0) continue;
    const int c = static_cast<int>(sizes.size());
    sizes.push_back(0);
    stack.push_back(s);
    label[static_cast<size_t>(s)] = c;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      ++sizes.back();
      for (SparseMatrix::InnerIterator it(A, v); it; ++it) {
        const int w = static_cast<int>(it.row());
        if (removed[static_cast<size_t>(w)] || label[static_cast<size_t>(w)] >= 0) continue;
        label[static_cast<size_t>(w)] = c;
        stack.push_back(w);
      }
    }
  }
  return sizes;
}

}  // namespace

TEST(FewestFlops, KeepsTheSmallestEstimateAndTheEarlierOnATie) {
  EXPECT_EQ(fewest_flops({{"metis", 3e9}, {"pord", 2e9}, {"amf", 2.5e9}, {"amd", 2.2e9}}), 1);
  EXPECT_EQ(fewest_flops({{"metis", 2e9}, {"pord", 2e9}}), 0);
  EXPECT_EQ(fewest_flops({{"amd", 1e6}}), 0);
}

TEST(FewestFlops, SkipsFailedAnalysesAndSaysWhenAllFailed) {
  EXPECT_EQ(fewest_flops({{"metis", kNaN}, {"pord", 5e9}, {"amd", 4e9}}), 2);
  EXPECT_EQ(fewest_flops({{"metis", 1e9}, {"pord", kNaN}}), 0);
  EXPECT_EQ(fewest_flops({{"metis", kNaN}, {"pord", kNaN}}), -1);
  EXPECT_EQ(fewest_flops({}), -1);
}

// Nested dissection orders a separator of the graph last: on the 40 x 40 grid, removing the
// vertices of the last pivots splits the rest into two parts of at least a quarter each after at
// most 60 of them (a straight cut has 40; a diagonal one cutting off a corner of a quarter, 29).
// The natural order's last 60 (a row and a half) do not disconnect the grid at all: the test
// tells the two apart.
TEST(NestedDissection, OrdersABalancedSeparatorLast) {
  if (!nested_dissection_available()) GTEST_SKIP() << "built without METIS";
  constexpr int kSide = 40, kMostSeparator = 60;
  const SparseMatrix A = grid(kSide, kSide);
  const int n = kSide * kSide;
  const std::vector<int> position = order_of(A);
  ASSERT_EQ(std::ssize(position), n);
  std::vector<int> sorted = position;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> identity(static_cast<size_t>(n));
  std::iota(identity.begin(), identity.end(), 0);
  ASSERT_EQ(sorted, identity) << "not a permutation";

  auto split_after = [&](const std::vector<int>& pos) {
    std::vector<bool> removed(static_cast<size_t>(n), false);
    for (int s = 1; s <= kMostSeparator; ++s) {
      for (int v = 0; v < n; ++v)
        if (pos[static_cast<size_t>(v)] == n - s) removed[static_cast<size_t>(v)] = true;
      std::vector<int> parts = components(A, removed);
      std::sort(parts.rbegin(), parts.rend());
      if (parts.size() >= 2 && parts[1] >= n / 4) return s;
    }
    return -1;
  };
  const int separator = split_after(position);
  EXPECT_GT(separator, 0) << "METIS's last 60 pivots do not split the grid into balanced parts";
  EXPECT_EQ(split_after(identity), -1);
}

// The ordering is of A + A^T: a pattern with only its upper triangle gets the same order.
TEST(NestedDissection, OrdersThePatternOfAPlusATranspose) {
  if (!nested_dissection_available()) GTEST_SKIP() << "built without METIS";
  EXPECT_EQ(order_of(grid(30, 20, true, true)), order_of(grid(30, 20, true)));
  EXPECT_TRUE(order_of(SparseMatrix(0, 0)).empty());
}

// A pattern without off-diagonal entries has no graph for METIS (which fails on one): any order
// is as good, and the identity comes back; MUMPS's `metis` then factorises the diagonal.
TEST(NestedDissection, ADiagonalPatternGetsTheIdentity) {
  if (!nested_dissection_available()) GTEST_SKIP() << "built without METIS";
  SparseMatrix D(5, 5);
  for (int i = 0; i < 5; ++i) D.insert(i, i) = 2.0 + i;
  D.makeCompressed();
  EXPECT_EQ(order_of(D), (std::vector<int>{0, 1, 2, 3, 4}));
  if (!mumps_available()) return;
  SparseLUOptions o;
  o.backend = SparseLUOptions::Backend::Mumps;
  o.ordering = SparseLUOptions::Ordering::Metis;
  SparseLU lu(o);
  ASSERT_TRUE(lu.factorize(D).is_ok());
  Vector x;
  ASSERT_TRUE(lu.solve(Vector::Ones(5), x).is_ok());
  EXPECT_NEAR(x[4], 1.0 / 6.0, 1e-15);
}

// MUMPS's `best` analyses each candidate and keeps the fewest estimated flops: the ordering it
// reports is the trials' argmin, and its flops are that trial's. On a long strip (600 x 6,
// 9-point) a minimum-degree ordering wins by far (AMD 5.0e5 flops against 8.6e5 for PORD and 1.0e6
// for METIS, MUMPS 5.5.1); on the square (150 x 150, 5-point) PORD's nested dissection does (6.1e7
// against 8.1e7 METIS and 9.1e7 AMD): the choice follows the pattern, it is not a constant.
TEST(BestOrdering, KeepsTheCandidateOfFewestFlopsAndItDependsOnThePattern) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  SparseLUOptions o;
  o.backend = SparseLUOptions::Backend::Mumps;
  o.ordering = SparseLUOptions::Ordering::Best;
  std::vector<std::string> winners;
  for (const SparseMatrix& A : {grid(600, 6, true), grid(150, 150)}) {
    SparseLU lu(o);
    ASSERT_TRUE(lu.factorize(A).is_ok());
    const SparseLU::Statistics& s = lu.statistics();
    const size_t candidates = nested_dissection_available() ? 3 : 2;
    ASSERT_EQ(s.ordering_trials.size(), candidates);
    EXPECT_EQ(s.ordering_trials.front().name, nested_dissection_available() ? "metis" : "pord");
    const int best = fewest_flops(s.ordering_trials);
    ASSERT_GE(best, 0);
    EXPECT_EQ(s.ordering_used, s.ordering_trials[static_cast<size_t>(best)].name);
    for (const OrderingTrial& t : s.ordering_trials)
      EXPECT_GE(t.flops, s.ordering_trials[static_cast<size_t>(best)].flops);
    // the kept analysis is the winner's (its estimate, against the factorisation's count, to 10%)
    EXPECT_NEAR(s.flops / s.ordering_trials[static_cast<size_t>(best)].flops, 1.0, 0.1);
    const Vector b = Vector::LinSpaced(A.rows(), -1, 1);
    Vector x;
    ASSERT_TRUE(lu.solve(b, x).is_ok());
    EXPECT_LT((A * x - b).norm() / b.norm(), 1e-13);
    winners.push_back(s.ordering_used);
  }
  EXPECT_NE(winners[0], winners[1]);
  EXPECT_EQ(winners[0], "amd");  // by a factor 1.7 in flops: not a close call
}

// A new pattern analysed by `best` in a fresh instance (here a structurally singular one, an empty
// row and column) is factorised on the kept winner, not on the earlier pattern's analysis: the
// singular status the callers fall back on, and no factors.
TEST(BestOrdering, ANewSingularPatternEndsInTheSingularStatus) {
  if (!mumps_available()) GTEST_SKIP() << "built without MUMPS";
  SparseLUOptions o;
  o.backend = SparseLUOptions::Backend::Mumps;
  o.ordering = SparseLUOptions::Ordering::Best;
  SparseLU lu(o);
  ASSERT_TRUE(lu.factorize(grid(6, 5)).is_ok());
  SparseMatrix S = grid(6, 5);
  S.prune([](int i, int j, double) { return i != 7 && j != 7; });
  S.makeCompressed();
  const Status st = lu.factorize(S);
  EXPECT_FALSE(st.is_ok());
  EXPECT_EQ(st.code(), StatusCode::SingularMatrix) << st.message();
  EXPECT_FALSE(lu.factorized());
}

// `ordering = "metis"` with MUMPS is METIS's nested dissection (not MUMPS's fallback to SCOTCH),
// solves exactly, and a second factorisation object of the same pattern reuses the order.
TEST(BestOrdering, MetisIsGivenToMumpsAndReused) {
  if (!mumps_available() || !nested_dissection_available()) GTEST_SKIP() << "built without MUMPS or METIS";
  SparseLUOptions o;
  o.backend = SparseLUOptions::Backend::Mumps;
  o.ordering = SparseLUOptions::Ordering::Metis;
  const SparseMatrix A = grid(70, 50, true);
  SparseLU first(o), second(o);
  ASSERT_TRUE(first.factorize(A).is_ok());
  EXPECT_EQ(first.statistics().ordering_used, "metis");
  EXPECT_TRUE(first.statistics().ordering_trials.empty());
  SparseMatrix B = A;
  B.coeffs() *= 2.0;
  ASSERT_TRUE(second.factorize(B).is_ok());
  EXPECT_EQ(second.statistics().analyses_reused, 1);
  EXPECT_EQ(second.statistics().ordering_used, "metis");
  EXPECT_EQ(second.statistics().nnz_lu, first.statistics().nnz_lu);
  const Vector b = Vector::Ones(A.rows());
  Vector x;
  ASSERT_TRUE(second.solve(b, x).is_ok());
  EXPECT_LT((B * x - b).norm() / b.norm(), 1e-13);
}

// The graph is merged from sorted columns: a pattern whose rows are out of order or repeated in a
// column (not Eigen's compressed form, and refused by UMFPACK too) is refused, not ordered wrongly.
TEST(NestedDissection, RefusesColumnsWithUnsortedOrRepeatedRows) {
  if (!nested_dissection_available()) GTEST_SKIP() << "built without METIS";
  const SparseMatrix A = grid(25, 17, true);
  for (const bool repeat : {false, true}) {
    std::vector<int> outer{0}, inner;
    for (int j = 0; j < A.cols(); ++j) {
      std::vector<int> rows(A.innerIndexPtr() + A.outerIndexPtr()[j], A.innerIndexPtr() + A.outerIndexPtr()[j + 1]);
      if (repeat)
        rows.push_back(rows.back());
      else
        std::reverse(rows.begin(), rows.end());
      inner.insert(inner.end(), rows.begin(), rows.end());
      outer.push_back(static_cast<int>(inner.size()));
    }
    EXPECT_THROW(nested_dissection_order(static_cast<int>(A.rows()), outer.data(), inner.data()), std::invalid_argument)
        << (repeat ? "repeated" : "unsorted");
  }
}
