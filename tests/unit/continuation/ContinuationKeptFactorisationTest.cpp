// The continuation engine on a kept factorisation: Anderson mixing, Deuflhard's test, the start's
// single factorisation, determinant signs, restarts from located points, the rounding floor, and
// branch points found without a factorisation at every point.
#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <random>

#include "continuation/Continuation.hpp"
#include "continuation/engine/BorderedSystem.hpp"
#include "continuation/engine/Hermite.hpp"
#include "core/ConvergenceTest.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "support/ContinuationTestSupport.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using namespace keller::test;

namespace {

// F_i = (1 + c_i lambda) u_i - 1, u_i = 1 / (1 + c_i lambda): a factorisation kept from lambda0
// leaves the chord the rates 1 - (1 + c_i lambda) / (1 + c_i lambda0), of both signs (slow and
// oscillating modes), like the old matrix of a real branch.
class SpreadLinear final : public DiagonalProblem {
 public:
  SpreadLinear() : DiagonalProblem("spread-linear", 4, 0.0) {}
  static constexpr double c[4] = {1.0, -0.35, 0.5, 2.0};
  static double exact(int i, double lambda) { return 1.0 / (1.0 + c[i] * lambda); }
  Vector initial_guess() override { return Vector::Ones(4); }

 private:
  double f(int i, double u, double l) const override { return (1 + c[i] * l) * u - 1; }
  double df_du(int i, double, double l) const override { return 1 + c[i] * l; }
  double df_dlambda(int i, double u, double) const override { return c[i] * u; }
};

// A kept factorisation never renewed while the chord converges, steps of 0.3 from 0 to 1.5.
ContinuationOptions spread_options(int anderson_depth) {
  ContinuationOptions o = kept_chord_options(0.3, 1.5, 200, {});
  o.corrector.renewal_cost = 1000;
  o.corrector.anderson_depth = anderson_depth;
  return o;
}

}  // namespace

// anderson_depth: the chord on a kept factorisation, accelerated. On a linear problem with four
// distinct chord rates it is GMRES: at most 4 + 1 updates to the solution (one more for
// rounding), where the plain chord contracts by its slowest rate (up to 0.55 here) per iteration.
// Same steps, the same points to the tolerance, no more factorisations.
TEST(Continuation, AndersonAccelerationShortensTheKeptChord) {
  auto trace = [](int depth, RecordingObserver& rec) {
    SpreadLinear p;
    return trace_from_guess(p, spread_options(depth), rec);
  };
  RecordingObserver plain, accelerated;
  const ContinuationResult r0 = trace(0, plain), r1 = trace(4, accelerated);
  ASSERT_EQ(r0.code, StopCode::UpperBound) << r0.reason;
  ASSERT_EQ(r1.code, StopCode::UpperBound) << r1.reason;
  ASSERT_EQ(plain.points.size(), accelerated.points.size());
  int most_plain = 0, most_accelerated = 0;
  for (size_t k = 1; k < plain.points.size(); ++k) {
    most_plain = std::max(most_plain, plain.points[k].iterations);
    most_accelerated = std::max(most_accelerated, accelerated.points[k].iterations);
    const BranchPoint& q = accelerated.points[k];
    EXPECT_DOUBLE_EQ(q.lambda, plain.points[k].lambda);
    EXPECT_LE(q.residual, 1e-10);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(q.u[i], SpreadLinear::exact(i, q.lambda), 1e-10) << q.lambda;
  }
  std::cout << "most corrector iterations in a step: plain " << most_plain << ", depth 4 " << most_accelerated
            << "; factorisations " << r0.factorisations << " and " << r1.factorisations << "; tangent solves "
            << r0.tangent_iterations << " and " << r1.tangent_iterations << "\n";
  EXPECT_LE(most_accelerated, 6);
  EXPECT_GE(most_plain, 15);
  EXPECT_LE(r1.factorisations, r0.factorisations);
  EXPECT_LT(r1.tangent_iterations, r0.tangent_iterations);
}

// The same under the pseudo-arclength row, where lambda is an unknown and the problem is bilinear
// in (u, lambda): the accelerated update must keep the arclength row (each point where the plain
// chord puts it) and still shorten the chord.
TEST(Continuation, AndersonAccelerationKeepsTheArclengthRow) {
  auto trace = [](int depth, RecordingObserver& rec) {
    SpreadLinear p;
    ContinuationOptions o = spread_options(depth);
    o.method = ContinuationOptions::Method::Arclength;
    o.events.land_on_values = false;
    o.step.growth = 1.0;             // the same steps in both runs
    o.step.target_iterations = 200;  // (never shrunk)
    return trace_from_guess(p, o, rec);
  };
  RecordingObserver plain, accelerated;
  const ContinuationResult r0 = trace(0, plain), r1 = trace(4, accelerated);
  ASSERT_EQ(r0.code, StopCode::UpperBound) << r0.reason;
  ASSERT_EQ(r1.code, StopCode::UpperBound) << r1.reason;
  ASSERT_EQ(plain.points.size(), accelerated.points.size());
  int total_plain = 0, total_accelerated = 0;
  for (size_t k = 1; k + 1 < plain.points.size(); ++k) {  // (the last is located on the bound)
    const BranchPoint& q = accelerated.points[k];
    total_plain += plain.points[k].iterations;
    total_accelerated += q.iterations;
    // a point off the arclength row would converge elsewhere on the branch
    EXPECT_NEAR(q.lambda, plain.points[k].lambda, 1e-9);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(q.u[i], SpreadLinear::exact(i, q.lambda), 1e-10) << q.lambda;
  }
  std::cout << plain.points.size() << " rows; corrector iterations: plain " << total_plain << ", depth 4 "
            << total_accelerated << "\n";
  EXPECT_LT(2 * total_accelerated, total_plain);
}

namespace {

// F = atan(u - lambda^3): u = lambda^3. Newton on atan(e) diverges from |e| > 1.39 with |F| rising
// towards pi/2, never by the 1e3 that counts as divergence: a step predicted that far off must
// be rejected at its first Newton iteration, whose simplified correction (on the same Jacobian)
// is longer than the Newton correction, not after a Jacobian per iteration.
class AtanCubic final : public DiagonalProblem {
 public:
  AtanCubic() : DiagonalProblem("atan-cubic", 1, 1.0) {}
  Vector initial_guess() override { return Vector::Ones(1); }

 private:
  double f(int, double u, double l) const override { return std::atan(u - l * l * l); }
  double df_du(int, double u, double l) const override { return 1.0 / (1.0 + std::pow(u - l * l * l, 2)); }
  double df_dlambda(int, double u, double l) const override { return -3.0 * l * l * df_du(0, u, l); }
};

}  // namespace

TEST(Continuation, AStepOutsideNewtonsRegionOfContractionIsRejectedAtOnce) {
  auto trace = [](double first_step, RecordingObserver& rec) {
    AtanCubic p;
    ContinuationOptions o = kept_chord_options(1.0, 3.0, 20, {});
    o.step.initial = first_step;
    return trace_from_guess(p, o, rec);
  };
  // the first step of 1 predicts e = 4 and is halved; compared with a branch started with the
  // halved step (no rejection; 7 rows either way)
  RecordingObserver rec, halved;
  const ContinuationResult r = trace(1.0, rec), h = trace(0.5, halved);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  ASSERT_EQ(h.code, StopCode::UpperBound) << h.reason;
  int raised = 0;
  for (const std::string& why : rec.rejections) raised += why.find("monotonicity test") != std::string::npos;
  std::cout << rec.points.size() << " rows, " << r.rejected << " rejected, " << r.factorisations
            << " factorisations; started with the halved step: " << h.factorisations << "\n";
  EXPECT_GE(raised, 1);  // the case this is about
  for (const BranchPoint& q : rec.points) EXPECT_NEAR(q.u[0], std::pow(q.lambda, 3), 1e-9);
  // each rejected attempt costs one Jacobian, its Newton iteration's (without the test the
  // attempt renewed the Jacobian at each of its iterations: 12 factorisations instead of 4,
  // against 5 from the halved step)
  EXPECT_LE(r.factorisations, h.factorisations + r.rejected);
}

// The start's J is factorised once: the initial tangent's block factorisation takes the
// arclength row through its Schur complement (it was factorised a second time at the same point,
// a whole factorisation per branch). A small first step's chord and tangent converge on it.
TEST(Continuation, TheStartIsFactorisedOnce) {
  ScaledLinear p(3);
  ContinuationOptions o = kept_chord_options(0.01, 2.0, 30, {});
  o.method = ContinuationOptions::Method::Arclength;
  o.stop.max_steps = 1;
  Continuation cont(p, o);
  RecordingObserver rec;
  const ContinuationResult r = cont.run(p.initial_guess(), rec);
  ASSERT_EQ(r.code, StopCode::MaxSteps) << r.reason;
  ASSERT_EQ(rec.points.size(), 2u);
  EXPECT_EQ(r.factorisations, 1);
  // det [J b; c^T d] = det J (d - c^T J^-1 b), and with the start's own unit tangent as the row
  // (tu = -J^-1 b tl) the second factor is (wl tl^2 + wu |tu|^2) / tl = 1 / tl > 0: the sign of
  // det J, which is positive here (J = diag((1 + lambda)(1 + i)))
  EXPECT_EQ(rec.points[0].bordered_det_sign, 1);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(rec.points[1].u[i], 1.0 / ((1 + rec.points[1].lambda) * (1 + i)), 1e-10);
}

// The sign of det J is reported only where J was factorised at the point. On the trivial branch
// of the pitchfork (F_p = 0) a tangent by iteration on a kept factorisation is exact from any
// matrix, also past the branch points where det J changes sign: the kept sign was reported there
// (wrong after each crossing). Every reported sign must be det J's at its point (dense LU); the
// points whose tangent came by iteration report 0.
TEST(Continuation, TheDeterminantSignIsReportedOnlyWhereJWasFactorised) {
  Pitchfork1DProblem p(20, 1.0, 0.0);
  ContinuationOptions o = test::pitchfork_trivial_options();
  o.corrector.method = CorrectorOptions::Method::Chord;
  o.corrector.block_elimination = true;
  o.corrector.keep = true;
  o.events.branch_points = false;
  o.corrector.anderson_depth = 5;
  Continuation cont(p, o);
  RecordingObserver rec;
  const ContinuationResult r = cont.run(Vector::Zero(p.size()), rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  int reported = 0, by_iteration = 0, past_a_crossing = 0;
  for (const BranchPoint& q : rec.points) {
    Vector F;
    SparseMatrix J;
    p.parameters().set(0, q.lambda);
    ASSERT_TRUE(p.jacobian(q.u, F, J).is_ok());
    const int truth = Eigen::MatrixXd(J).partialPivLu().determinant() > 0 ? 1 : -1;
    if (q.det_sign == 0) {
      ++by_iteration;
    } else {
      ++reported;
      EXPECT_EQ(q.det_sign, truth) << "lambda = " << q.lambda;
    }
    past_a_crossing += q.lambda > 4.0 * 400.0 * std::pow(std::sin(M_PI / 40.0), 2);  // lambda_1 of the mesh
  }
  std::cout << rec.points.size() << " rows: " << reported << " with the sign of det J, " << by_iteration
            << " by iteration (0)\n";
  EXPECT_GT(reported, 0);
  EXPECT_GT(by_iteration, 0);
  EXPECT_GT(past_a_crossing, 0);
}

// A restart from a stored located fold starts on the fold itself, where the sign of the tangent's
// parameter part is rounding: its first step must not locate the same fold again (it did, as the
// restarted branch's first located point). The restarted branch ends where the original does.
TEST(Continuation, ARestartFromALocatedFoldDoesNotLocateItAgain) {
  for (const bool newton : {false, true}) {
    SCOPED_TRACE(newton ? "newton" : "kept chord");
    Bratu1DProblem p(128, 0.0);
    ContinuationOptions o = test::bratu_fold_options("u_mid", 4.0);
    if (newton) {
      o.corrector.method = CorrectorOptions::Method::Newton;
      o.corrector.block_elimination = false;
    }
    Continuation first(p, o);
    RecordingObserver rec;
    ASSERT_EQ(first.run(p.initial_guess(), rec).code, StopCode::StopObservable);
    const auto folds = rec.of_kind(PointKind::Fold);
    ASSERT_EQ(folds.size(), 1u);
    ContinuationOptions again = o;
    again.state_scale = first.state_scale();
    Continuation second(p, again);
    RecordingObserver rec2;
    p.parameters().set("lambda", folds[0]->lambda);
    ASSERT_EQ(second.resume(*folds[0], rec2).code, StopCode::StopObservable) << rec2.reason;
    EXPECT_TRUE(rec2.of_kind(PointKind::Fold).empty())
        << "fold at lambda = " << rec2.of_kind(PointKind::Fold)[0]->lambda;
    EXPECT_NEAR(rec2.points.back().lambda, rec.points.back().lambda, 1e-8);
  }
}

// 1D Bratu on 2000 intervals to 1e-12: its residual cannot fall below about 3e-9 (eps |J| |u|,
// |J| = 4 / h^2), above 1e3 times the tolerance. The corrector stops at that floor, as core's
// Newton does, and the branch passes the fold (it ended before it at the step floor, every
// correction near the fold counted as not converged). The fold of this mesh lies within
// 1e-6 of the continuum's 3.513830719 (h^2 = 2.5e-7).
TEST(Continuation, TheCorrectorStopsAtTheProblemsRoundingFloor) {
  for (const bool newton : {false, true}) {
    SCOPED_TRACE(newton ? "newton" : "kept chord");
    Bratu1DProblem p(2000, 0.0);
    ContinuationOptions o = test::bratu_fold_options("u_mid", 1.5);
    o.events.tolerance = 1e-9;
    if (newton) {
      o.corrector.method = CorrectorOptions::Method::Newton;
      o.corrector.block_elimination = false;
    }
    NewtonOptions tight;
    tight.residual_tolerance = 1e-12;
    Continuation cont(p, o, tight);
    RecordingObserver rec;
    const ContinuationResult r = cont.run(p.initial_guess(), rec);
    ASSERT_EQ(r.code, StopCode::StopObservable) << r.reason;
    const auto folds = rec.of_kind(PointKind::Fold);
    ASSERT_EQ(folds.size(), 1u);
    EXPECT_NEAR(folds[0]->lambda, 3.513830719125, 1e-6);
    Vector F;
    SparseMatrix J;
    p.parameters().set("lambda", folds[0]->lambda);
    ASSERT_TRUE(p.jacobian(folds[0]->u, F, J).is_ok());
    const double floor = std::max(kRoundingFloorBand * 1e-12, rounding_floor(J, folds[0]->u));
    std::cout << rec.points.size() << " rows, " << r.factorisations << " factorisations, fold at " << folds[0]->lambda
              << "; floor level " << floor << "\n";
    EXPECT_GT(floor, 1e3 * 1e-12);  // the case this is about
    for (const BranchPoint& q : rec.points) EXPECT_LE(q.residual, floor) << "lambda = " << q.lambda;
  }
}

// Branch points with the fast defaults (a kept factorisation, tangents by iteration): on the
// trivial pitchfork branch the chord never renews (F_p = 0, u = 0 solves every step at once), so
// the determinant's sign comes from probes every kBranchPointProbeRows rows and at the end; a
// change is bracketed by probing the rows between and located as with a factorisation at every
// point: the same two branch points, with a fraction of the factorisations.
TEST(Continuation, BranchPointsAreFoundOnAKeptFactorisation) {
  const int n = 50;
  auto trace = [&](bool exact, RecordingObserver& rec) {
    Pitchfork1DProblem p(n, 1.0);
    ContinuationOptions o = test::pitchfork_trivial_options();
    if (exact) {
      o.corrector.method = CorrectorOptions::Method::Newton;
      o.corrector.block_elimination = false;
    }
    Continuation cont(p, o);
    return cont.run(p.initial_guess(), rec);
  };
  RecordingObserver kept, exact;
  const ContinuationResult rk = trace(false, kept), re = trace(true, exact);
  ASSERT_EQ(rk.code, StopCode::UpperBound) << rk.reason;
  ASSERT_EQ(re.code, StopCode::UpperBound) << re.reason;
  const auto a = kept.of_kind(PointKind::BranchPoint), b = exact.of_kind(PointKind::BranchPoint);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(a[k]->lambda, Pitchfork1DProblem::branch_point(k + 1, n), 1e-8);
    EXPECT_NEAR(a[k]->lambda, b[k]->lambda, 1e-8);
  }
  std::cout << "kept: " << kept.points.size() << " rows, " << rk.factorisations << " factorisations, "
            << rk.tangent_iterations << " tangent solves by iteration; exact: " << exact.points.size() << " rows, "
            << re.factorisations << " factorisations\n";
  EXPECT_GT(rk.tangent_iterations, 0);
  EXPECT_LT(2 * rk.factorisations, re.factorisations);
}

// A branch that lands on its bound learns the sign of det at its end from the last step's own
// factorisation (made at its first correction), not from a probe after it: on the trivial pitchfork
// branch below its first branch point the chord never renews, so the start and the last step are
// the only factorisations, and no probe is made.
TEST(Continuation, ABranchEndingOnABoundTakesItsLastSignFromItsLastStep) {
  Pitchfork1DProblem p(50, 1.0);
  ContinuationOptions o = test::pitchfork_trivial_options();
  o.stop.upper = 0.5 * Pitchfork1DProblem::branch_point(1, 50);
  Continuation cont(p, o);
  RecordingObserver rec;
  const ContinuationResult r = cont.run(p.initial_guess(), rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  ASSERT_GE(rec.points.size(), 4u);
  EXPECT_EQ(rec.points.back().lambda, o.stop.upper);
  EXPECT_EQ(r.probes, 0);
  EXPECT_EQ(r.factorisations, 2);
  EXPECT_EQ(rec.points.back().bordered_det_sign, rec.points.front().bordered_det_sign);
  EXPECT_NE(rec.points.back().bordered_det_sign, 0);
  EXPECT_TRUE(rec.of_kind(PointKind::BranchPoint).empty());
}
