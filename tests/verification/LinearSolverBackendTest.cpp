// The two sparse LU backends (UMFPACK; MUMPS where keller is built with it) trace the same
// branches: the branch points the determinant's sign finds and the folds the tangent finds are
// located at the same parameter values, to the tolerance they are located to.
#include <gtest/gtest.h>

#include <iomanip>
#include <iostream>

#include "continuation/Continuation.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using Backend = SparseLUOptions::Backend;

namespace {

struct Located {
  ContinuationResult result;
  std::vector<double> branch_points, folds;
};

Located trace(Problem& p, const ContinuationOptions& o, Backend backend) {
  SparseLUOptions lu;
  lu.backend = backend;
  Continuation cont(p, o, {}, lu);
  test::RecordingObserver rec;
  Located out;
  out.result = cont.run(p.initial_guess(), rec);
  for (const BranchPoint* q : rec.of_kind(PointKind::BranchPoint)) out.branch_points.push_back(q->lambda);
  for (const BranchPoint* q : rec.of_kind(PointKind::Fold)) out.folds.push_back(q->lambda);
  return out;
}

class BothBackends : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!mumps_available()) GTEST_SKIP() << "built without MUMPS: one backend only";
  }
};

}  // namespace

// The trivial branch of u'' + lambda u - u^3 = 0 through its first two branch points, found by
// the sign of the bordered determinant (no spectrum): the same two points with both backends, each
// within 1e-8 of the discrete eigenvalue lambda_k (as Stability.* asserts for the spectrum), and
// within twice the location tolerance of each other (each lies within it of the same crossing).
TEST_F(BothBackends, PitchforkBranchPointsByTheDeterminantAgree) {
  const ContinuationOptions o = test::pitchfork_trivial_options();
  constexpr int kIntervals = 32;
  Located runs[2];
  const Backend backends[2] = {Backend::Umfpack, Backend::Mumps};
  for (int b = 0; b < 2; ++b) {
    Pitchfork1DProblem p(kIntervals, 1.0);
    runs[b] = trace(p, o, backends[b]);
    ASSERT_EQ(runs[b].result.code, StopCode::UpperBound) << to_string(backends[b]) << ": " << runs[b].result.reason;
    ASSERT_EQ(runs[b].branch_points.size(), 2u) << to_string(backends[b]);
    for (int k = 1; k <= 2; ++k)
      EXPECT_NEAR(runs[b].branch_points[k - 1], Pitchfork1DProblem::branch_point(k, kIntervals), 1e-8)
          << to_string(backends[b]) << ", k = " << k;
  }
  for (int k = 0; k < 2; ++k) {
    std::cout << std::setprecision(15) << "branch point " << k + 1 << ": umfpack " << runs[0].branch_points[k]
              << ", mumps " << runs[1].branch_points[k] << "\n";
    EXPECT_NEAR(runs[0].branch_points[k], runs[1].branch_points[k], 2 * o.events.tolerance) << "k = " << k + 1;
  }
}

// Bratu's fold, located by the tangent's parameter component: the same value with both backends,
// within twice the location tolerance.
TEST_F(BothBackends, BratuFoldAgrees) {
  const ContinuationOptions o = test::bratu_fold_options("u_mid", 4.0);
  double fold[2];
  const Backend backends[2] = {Backend::Umfpack, Backend::Mumps};
  for (int b = 0; b < 2; ++b) {
    Bratu1DProblem p(64, 0.0);
    const Located r = trace(p, o, backends[b]);
    ASSERT_EQ(r.result.code, StopCode::StopObservable) << to_string(backends[b]) << ": " << r.result.reason;
    ASSERT_EQ(r.folds.size(), 1u) << to_string(backends[b]);
    EXPECT_TRUE(r.branch_points.empty()) << to_string(backends[b]);
    fold[b] = r.folds[0];
  }
  std::cout << std::setprecision(15) << "fold: umfpack " << fold[0] << ", mumps " << fold[1] << "\n";
  EXPECT_NEAR(fold[0], fold[1], 2 * o.events.tolerance);
}
