// The BLAS thread policy (core/BlasThreads): as a function on sizes, and through SparseLU, which sets
// it when it analyses a matrix where the policy is on (a command-line program), and not where it is
// off (the Python package). The suite runs with OPENBLAS_NUM_THREADS=1; tests/CMakeLists.txt
// runs these tests once more with 2, where a policy that sets nothing or never gives the threads
// back fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "core/BlasThreads.hpp"
#include "core/SparseLU.hpp"

using namespace keller;

namespace {

// A tridiagonal, diagonally dominant n x n matrix: cheap to factorise at any n.
SparseMatrix tridiagonal(int n) {
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0);
    if (i > 0) t.emplace_back(i, i - 1, -1.0);
    if (i + 1 < n) t.emplace_back(i, i + 1, -1.0);
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

}  // namespace

TEST(BlasThreads, OneThreadBelowTheThresholdTheBlasOwnCountAbove) {
  EXPECT_EQ(blas_threads_for_unknowns(1944, 2), 1);  // the coarse channel of the orbit benchmark
  EXPECT_EQ(blas_threads_for_unknowns(kThreadedBlasUnknowns - 1, 8), 1);
  EXPECT_EQ(blas_threads_for_unknowns(kThreadedBlasUnknowns, 8), 8);
  EXPECT_EQ(blas_threads_for_unknowns(132381, 2), 2);  // the cylinder's W3
  EXPECT_EQ(blas_threads_for_unknowns(132381, 1), 1);  // a user's OPENBLAS_NUM_THREADS=1 stays
  EXPECT_EQ(blas_threads_for_unknowns(132381, 0), 1);  // never fewer than one
  EXPECT_EQ(blas_threads_for_unknowns(0, 4), 1);
}

TEST(BlasThreads, SparseLUSetsThePolicyWhenItAnalyses) {
  // the count for a large matrix: the BLAS's own when the process started
  const int large = use_blas_threads_for(kThreadedBlasUnknowns);
  if (large == 0) {
    GTEST_SKIP() << "the BLAS is not OpenBLAS: keller leaves its threads alone";
  }
  const char* env = std::getenv("OPENBLAS_NUM_THREADS");
  if (env && std::string(env) == "2") {  // OpenBLAS takes at most the cores
    EXPECT_EQ(large, std::min(2, static_cast<int>(std::thread::hardware_concurrency())));
  }
  struct Policy {  // on for this test only, as the keller program has it
    Policy() { set_blas_thread_policy(true); }
    ~Policy() { set_blas_thread_policy(false); }
  } policy;
  SparseLU big, small;
  const SparseMatrix B = tridiagonal(static_cast<int>(kThreadedBlasUnknowns)), S = tridiagonal(500);
  ASSERT_TRUE(small.factorize(S).is_ok());
  EXPECT_EQ(blas_threads(), 1);
  ASSERT_TRUE(big.factorize(B).is_ok());
  EXPECT_EQ(blas_threads(), large);
  ASSERT_TRUE(small.analyze(S).is_ok());
  EXPECT_EQ(blas_threads(), 1);
  if (large < 2) {
    GTEST_SKIP() << "one BLAS thread to begin with: with OPENBLAS_NUM_THREADS=2 the test sees it change";
  }
}

TEST(BlasThreads, TheCommandLinesDefaultLeavesAProgramsChoice) {
  set_blas_thread_policy(false);     // as the Python package does: numpy shares the BLAS
  default_blas_thread_policy(true);  // as run_command_line does
  EXPECT_FALSE(blas_thread_policy());
  set_blas_thread_policy(true);
  default_blas_thread_policy(false);
  EXPECT_TRUE(blas_thread_policy());
  set_blas_thread_policy(false);
}

TEST(BlasThreads, WithThePolicyOffSparseLULeavesTheBlasAlone) {
  set_blas_thread_policy(false);
  const int large = use_blas_threads_for(kThreadedBlasUnknowns);
  if (large == 0) {
    GTEST_SKIP() << "the BLAS is not OpenBLAS: keller leaves its threads alone";
  }
  SparseLU small;
  ASSERT_TRUE(small.factorize(tridiagonal(500)).is_ok());
  EXPECT_EQ(blas_threads(), large);
  if (large < 2) {
    GTEST_SKIP() << "one BLAS thread to begin with: with OPENBLAS_NUM_THREADS=2 the test sees it kept";
  }
}
