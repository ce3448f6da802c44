// The BLAS thread policy (core/BlasThreads): as a function on sizes, through SparseLU, which sets
// it when it factorises a matrix where the policy is on (a command-line program) and not where it
// is off (the Python package), and the command line's default. The suite runs with
// OPENBLAS_NUM_THREADS=1; tests/CMakeLists.txt runs these tests once more with 2, where a policy
// that sets nothing or never gives the threads back fails.
#include <gtest/gtest.h>
#include <sched.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "core/BlasThreads.hpp"
#include "core/SparseLU.hpp"
#include "runs/CommandLine.hpp"

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

// The count OpenBLAS starts with, from what the test was given rather than from the code under
// test: 2 with OPENBLAS_NUM_THREADS=2 and at least two CPUs this process may run on; 0 where the
// test cannot know (then it checks what holds at any count).
int known_start_count() {
  const char* env = std::getenv("OPENBLAS_NUM_THREADS");
  cpu_set_t set;
  CPU_ZERO(&set);
  const int cpus = sched_getaffinity(0, sizeof(set), &set) == 0 ? CPU_COUNT(&set) : 0;
  return env && std::string(env) == "2" && cpus >= 2 ? 2 : 0;
}

struct PolicyOn {  // for one test, as a command-line program has it
  PolicyOn() { set_blas_thread_policy(true); }
  ~PolicyOn() { set_blas_thread_policy(false); }
};

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

TEST(BlasThreads, SparseLUSetsThePolicyWhenItFactorises) {
  if (blas_threads() == 0) GTEST_SKIP() << "the BLAS is not OpenBLAS: keller leaves its threads alone";
  const int start = known_start_count();
  const int large = use_blas_threads_for(kThreadedBlasUnknowns);  // the BLAS's own count
  if (start > 0) {
    EXPECT_EQ(large, start);
  }
  const PolicyOn policy;
  SparseLU big, small;
  const SparseMatrix B = tridiagonal(static_cast<int>(kThreadedBlasUnknowns)), S = tridiagonal(500);
  ASSERT_TRUE(small.factorize(S).is_ok());
  EXPECT_EQ(blas_threads(), 1);
  ASSERT_TRUE(big.factorize(B).is_ok());
  EXPECT_EQ(blas_threads(), large);
  ASSERT_TRUE(small.factorize(S).is_ok());  // the same pattern, no analysis: set again all the same
  EXPECT_EQ(blas_threads(), 1);
}

TEST(BlasThreads, WithThePolicyOffSparseLULeavesTheBlasAlone) {
  if (blas_threads() == 0) GTEST_SKIP() << "the BLAS is not OpenBLAS: keller leaves its threads alone";
  set_blas_thread_policy(false);  // as the Python package has it
  const int large = use_blas_threads_for(kThreadedBlasUnknowns);
  const int start = known_start_count();
  if (start > 0) {
    EXPECT_EQ(large, start);
  }
  SparseLU small;
  ASSERT_TRUE(small.factorize(tridiagonal(500)).is_ok());
  EXPECT_EQ(blas_threads(), large);
}

TEST(BlasThreads, TheCommandLinesDefaultLeavesAProgramsChoice) {
  set_blas_thread_policy(false);     // as the Python package does
  default_blas_thread_policy(true);  // as run_command_line does
  EXPECT_FALSE(blas_thread_policy());
  set_blas_thread_policy(true);
  default_blas_thread_policy(false);
  EXPECT_TRUE(blas_thread_policy());
  set_blas_thread_policy(false);
}

// `keller --version` through run_command_line in a process where nothing set the policy; exits 0
// where the command line turned it on
[[noreturn]] void version_then_exit_with_the_policy() {
  if (blas_thread_policy()) std::exit(2);
  std::string program = "keller", version = "--version";
  char* argv[] = {program.data(), version.data(), nullptr};
  run_command_line(2, argv);
  std::exit(blas_thread_policy() ? 0 : 1);
}

TEST(BlasThreadsDeathTest, TheCommandLineTurnsThePolicyOnWhereNothingSetIt) {
  // in a fresh process (the threadsafe style runs the test binary again): nothing has set it there
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(version_then_exit_with_the_policy(), testing::ExitedWithCode(0), "");
}

// The kernels' policy as a function: only OpenBLAS's generic Prescott fallback is replaced, by the
// widest kernels the CPU has; a CPU without AVX2 keeps it, and every other choice of OpenBLAS's
// (or another BLAS: "") stays.
TEST(BlasKernels, OnlyThePrescottFallbackIsReplacedByTheCpusOwn) {
  EXPECT_EQ(better_blas_core("Prescott", true, true), "SkylakeX");
  EXPECT_EQ(better_blas_core("Prescott", true, false), "Haswell");
  EXPECT_EQ(better_blas_core("PRESCOTT", true, false), "Haswell");
  EXPECT_EQ(better_blas_core("Prescott", false, false), "");
  EXPECT_EQ(better_blas_core("Haswell", true, true), "");
  EXPECT_EQ(better_blas_core("Zen", true, false), "");
  EXPECT_EQ(better_blas_core("SkylakeX", true, true), "");
  EXPECT_EQ(better_blas_core("", true, true), "");
}
