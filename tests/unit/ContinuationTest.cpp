// The continuation engine on problems with known answers: the bordered solve, folds and events
// located to tight tolerances, requested values hit exactly, natural continuation stopping at a
// fold, and numerical failures handled by step halving.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <random>

#include "continuation/BorderedSystem.hpp"
#include "continuation/Continuation.hpp"
#include "continuation/Hermite.hpp"
#include "core/ConvergenceTest.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using test::CubicProblem;
using test::RecordingObserver;

namespace {

SparseMatrix random_matrix(int n, unsigned seed, bool singular) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    D(i, i) = 3 + U(rng);
    D(i, (i + 1) % n) = U(rng);
    D((i + 2) % n, i) = U(rng);
  }
  if (singular) D.row(n - 1) = D.row(0) + D.row(1);  // rank n - 1, like J at a fold
  SparseMatrix A = D.sparseView(0.0, 0.0);
  for (int i = 0; i < n; ++i) A.coeffRef(i, i) += 0.0;  // keep the diagonal in the pattern
  A.makeCompressed();
  return A;
}

// The engine's exact-Newton path (a Jacobian per corrector iteration, the whole bordered matrix
// factorised): the location tests below count its iterations. The fast defaults (a kept chord)
// are the other tests'.
ContinuationOptions cubic_options() {
  ContinuationOptions o;
  o.corrector.method = CorrectorOptions::Method::Newton;
  o.corrector.block_elimination = false;
  o.parameter = "lambda";
  o.stop.lower = -5.0;
  o.stop.upper = 5.0;
  o.step.initial = 0.1;
  o.step.max = 0.3;
  o.events.tolerance = 1e-12;
  return o;
}

// The unit circle by arclength s: u = cos s, lambda = sin s, with its unit tangent.
BranchPoint circle_point(double s) {
  BranchPoint p;
  p.s = s;
  p.u = Vector::Constant(1, std::cos(s));
  p.lambda = std::sin(s);
  p.tu = Vector::Constant(1, -std::sin(s));
  p.tlambda = std::cos(s);
  return p;
}

// Options of the ScaledLinear tests: natural steps of the given size (one step to just past
// upper), the plain chord (no Anderson mixing, so that its rate is known exactly) with the
// factorisation kept across steps, renewed by the rate rule alone.
ContinuationOptions kept_chord_options(double step, double upper, int max_iterations, std::vector<double> stops) {
  ContinuationOptions o;
  o.parameter = "lambda";
  o.method = ContinuationOptions::Method::Natural;
  o.step.max_angle_degrees = 89;  // the tangent turns by up to about 45 degrees on one step
  o.stop.upper = upper;
  o.step.initial = step;
  o.step.max = step;
  o.corrector.method = CorrectorOptions::Method::Chord;
  o.corrector.block_elimination = true;
  o.corrector.keep = true;
  o.corrector.anderson_depth = 0;
  o.corrector.renewal_cost = 0.0;
  o.events.branch_points = false;
  o.step.target_iterations = 8;
  o.corrector.max_iterations = max_iterations;
  o.events.stops = std::move(stops);
  return o;
}

// Traces p from its initial guess with o.
ContinuationResult trace_from_guess(Problem& p, const ContinuationOptions& o, RecordingObserver& rec) {
  Continuation cont(p, o);
  return cont.run(p.initial_guess(), rec);
}

// (x, y) and the determinant sign against a dense LU of [J b; c^T d] (x, y) = (f, g): to 1e-12.
void expect_dense_solution(const SparseMatrix& J, const Vector& b, const Vector& c, double d, const Vector& f, double g,
                           const Vector& x, double y, int det_sign) {
  const long n = J.rows();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + 1, n + 1);
  A.topLeftCorner(n, n) = Eigen::MatrixXd(J);
  A.block(0, n, n, 1) = b;
  A.block(n, 0, 1, n) = c.transpose();
  A(n, n) = d;
  Vector rhs(n + 1);
  rhs << f, g;
  const Vector ref = A.fullPivLu().solve(rhs);
  EXPECT_LT((x - ref.head(n)).cwiseAbs().maxCoeff(), 1e-12 * ref.cwiseAbs().maxCoeff());
  EXPECT_NEAR(y, ref[n], 1e-12 * ref.cwiseAbs().maxCoeff());
  EXPECT_EQ(det_sign, A.determinant() > 0 ? 1 : -1);
}

}  // namespace

// Both ways of solving the bordered system (the whole matrix, and block elimination on J with
// its fallback to the whole matrix where J is singular) against a dense solve.
TEST(BorderedSystem, MatchesDenseSolveIncludingAtAFold) {
  for (auto mode : {BorderedSystem::Mode::Full, BorderedSystem::Mode::Block})
    for (bool singular : {false, true}) {
      SCOPED_TRACE(mode == BorderedSystem::Mode::Full ? "full" : "block");
      const int n = 12;
      const SparseMatrix J = random_matrix(n, 3, singular);
      const Vector b = Vector::LinSpaced(n, 1.0, 2.0), c = Vector::LinSpaced(n, -1.0, 0.5), f = Vector::Ones(n);
      const double d = 0.3, g = -0.7;
      BorderedSystem bs(J, {}, mode);
      bs.set(J, b, c, d);
      ASSERT_TRUE(bs.factorize().is_ok()) << "singular J = " << singular;
      Vector x;
      double y = 0;
      ASSERT_TRUE(bs.solve(f, g, x, y).is_ok());
      // block elimination cannot use a singular J: that system fell back to the whole matrix
      if (mode == BorderedSystem::Mode::Block) {
        EXPECT_EQ(bs.fallbacks(), singular ? 1 : 0);
      }
      expect_dense_solution(J, b, c, d, f, g, x, y, bs.determinant_sign());
    }
}

// Replacing the border row of a block factorisation (as the chord corrector does when it keeps
// J's factorisation across steps) gives the solution of the new bordered system, and the sign of
// its determinant, without a new factorisation.
TEST(BorderedSystem, NewBorderRowWithoutRefactorising) {
  const int n = 12;
  const SparseMatrix J = random_matrix(n, 3, false);
  const Vector b = Vector::LinSpaced(n, 1.0, 2.0), f = Vector::Ones(n);
  BorderedSystem bs(J, {}, BorderedSystem::Mode::Block);
  bs.set(J, b, Vector::LinSpaced(n, -1.0, 0.5), 0.3);
  ASSERT_TRUE(bs.factorize().is_ok());
  const Vector c2 = Vector::LinSpaced(n, 0.2, -0.9);
  const double d2 = -1.1, g = 0.4;
  ASSERT_TRUE(bs.set_row(c2, d2).is_ok());
  Vector x;
  double y = 0;
  ASSERT_TRUE(bs.solve(f, g, x, y).is_ok());
  EXPECT_EQ(bs.fallbacks(), 0);
  expect_dense_solution(J, b, c2, d2, f, g, x, y, bs.determinant_sign());
  // the whole-matrix mode cannot: the row is inside its factorisation
  BorderedSystem full(J, {}, BorderedSystem::Mode::Full);
  full.set(J, b, c2, d2);
  ASSERT_TRUE(full.factorize().is_ok());
  EXPECT_FALSE(full.set_row(c2, d2).is_ok());
}

TEST(Continuation, CubicFoldsLocatedTo1e10AndEndHitExactly) {
  CubicProblem problem(-2.0);  // u = -2 solves u^3 - 3u = -2
  Continuation cont(problem, cubic_options());
  RecordingObserver rec;
  const ContinuationResult r = cont.run(problem.initial_guess(), rec);
  const auto folds = rec.of_kind(PointKind::Fold);
  ASSERT_EQ(folds.size(), 2u) << r.reason;
  std::cout << "cubic folds at lambda = " << folds[0]->lambda << " and " << folds[1]->lambda << "\n";
  // the trial points start on the cubic Hermite interpolant of the bracket: 3 and 4 corrector
  // iterations in all (4 and 5 from the straight chord between the bracket's points)
  EXPECT_LE(folds[0]->iterations, 3);
  EXPECT_LE(folds[1]->iterations, 4);
  EXPECT_NEAR(folds[0]->lambda, 2.0, 1e-10);
  EXPECT_NEAR(folds[0]->u[0], -1.0, 1e-5);  // lambda - 2 = -3 (u + 1)^2 + ...: u to the square root
  EXPECT_EQ(folds[0]->label, "max");
  EXPECT_NEAR(folds[1]->lambda, -2.0, 1e-10);
  EXPECT_EQ(folds[1]->label, "min");
  // the branch ends exactly on the upper bound, and nothing lies beyond it
  EXPECT_EQ(r.code, StopCode::UpperBound);
  EXPECT_EQ(rec.points.back().kind, PointKind::End);
  EXPECT_EQ(rec.points.back().lambda, 5.0);
  for (const auto& p : rec.points) EXPECT_LE(p.lambda, 5.0);
  // every reported point is a solution
  for (const auto& p : rec.points) EXPECT_NEAR(std::pow(p.u[0], 3) - 3 * p.u[0], p.lambda, 1e-9);
  // det J = 3u^2 - 3 changes sign at each fold
  EXPECT_EQ(rec.points.front().det_sign, 1);
  EXPECT_EQ(rec.points.back().det_sign, 1);
}

TEST(Continuation, EventOnAMonitorWithAKnownCrossing) {
  CubicProblem problem(-2.0);
  ContinuationOptions o = cubic_options();
  o.events.tolerance = 1e-11;
  Continuation cont(problem, o);
  RecordingObserver rec;
  cont.run(problem.initial_guess(), rec);
  const auto events = rec.of_kind(PointKind::Event);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0]->label, "u - 1/2");
  std::cout << "event u = 1/2 located at lambda = " << events[0]->lambda << " (exact -1.375)\n";
  EXPECT_NEAR(events[0]->lambda, -1.375, o.events.tolerance);
  EXPECT_NEAR(events[0]->u[0], 0.5, 1e-9);
  // secant trials predicted on the cubic Hermite interpolant of the bracket: 9 corrector
  // iterations in all (11 from the straight chord between the bracket's points)
  EXPECT_LE(events[0]->iterations, 9);
}

// A stop observable whose threshold is a zero of a problem monitor (here u = 1/2 both ways) finds
// the same point twice: it is reported once, as the end of the branch.
TEST(Continuation, AStopThatIsAlsoAnEventIsReportedOnce) {
  CubicProblem problem(-2.0);
  ContinuationOptions o = cubic_options();
  o.events.tolerance = 1e-11;
  o.stop.observable = "u";
  o.stop.above = 0.5;
  Continuation cont(problem, o);
  RecordingObserver rec;
  const ContinuationResult r = cont.run(problem.initial_guess(), rec);
  ASSERT_EQ(r.code, StopCode::StopObservable) << r.reason;
  EXPECT_TRUE(rec.of_kind(PointKind::Event).empty());
  ASSERT_EQ(rec.of_kind(PointKind::End).size(), 1u);
  EXPECT_NEAR(rec.points.back().lambda, -1.375, o.events.tolerance);
  EXPECT_EQ(rec.points.back().kind, PointKind::End);
  // found once, too: the end is the event's zero (the same function), not a second search. With a
  // threshold 1e-7 away (another function) the search is made twice and costs more solves.
  {
    ContinuationOptions apart = o;
    apart.stop.above = 0.5 + 1e-7;
    CubicProblem p2(-2.0);
    Continuation c2(p2, apart);
    RecordingObserver rec_apart;
    const ContinuationResult r2 = c2.run(p2.initial_guess(), rec_apart);
    ASSERT_EQ(r2.code, StopCode::StopObservable) << r2.reason;
    ASSERT_EQ(rec_apart.of_kind(PointKind::Event).size(), 1u);
    const BranchPoint& end = rec.points.back();
    std::cout << "solves: " << r.timings.solves << " with the zero shared, " << r2.timings.solves
              << " searched twice; the end's search " << end.iterations << "\n";
    EXPECT_LE(r.timings.solves + end.iterations, r2.timings.solves);
  }
  // a requested value at the same place is another kind of point: it stays
  o.events.stops = {-1.375};
  Continuation again(problem, o);
  RecordingObserver rec2;
  problem.parameters().set("lambda", -2.0);
  again.run(problem.initial_guess(), rec2);
  // (the branch crosses lambda = -1.375 first at u = -1.93, then at the end, u = 1/2)
  ASSERT_EQ(rec2.of_kind(PointKind::Requested).size(), 2u);
  ASSERT_GE(rec2.points.size(), 2u);
  const BranchPoint& last_but_one = rec2.points[rec2.points.size() - 2];
  EXPECT_EQ(last_but_one.kind, PointKind::Requested);
  EXPECT_EQ(last_but_one.lambda, -1.375);
  EXPECT_NEAR(last_but_one.u[0], 0.5, 1e-9);
  EXPECT_TRUE(rec2.of_kind(PointKind::Event).empty());
  EXPECT_EQ(rec2.points.back().kind, PointKind::End);
}

TEST(Continuation, RequestedValuesAtEveryCrossing) {
  CubicProblem problem(-2.0);
  ContinuationOptions o = cubic_options();
  o.events.stops = {0.0, 1.0};
  Continuation cont(problem, o);
  RecordingObserver rec;
  cont.run(problem.initial_guess(), rec);
  int zero = 0, one = 0;
  for (const BranchPoint* p : rec.of_kind(PointKind::Requested)) {
    EXPECT_TRUE(p->lambda == 0.0 || p->lambda == 1.0);  // exactly
    (p->lambda == 0.0 ? zero : one)++;
    EXPECT_NEAR(std::pow(p->u[0], 3) - 3 * p->u[0], p->lambda, 1e-10);
  }
  EXPECT_EQ(zero, 3);  // u = -sqrt(3), 0, sqrt(3)
  EXPECT_EQ(one, 3);
  // rows are in order along the branch
  for (size_t i = 1; i < rec.points.size(); ++i) EXPECT_GT(rec.points[i].s, rec.points[i - 1].s);
}

TEST(Continuation, SecantPredictorAlsoPassesTheFolds) {
  CubicProblem problem(-2.0);
  ContinuationOptions o = cubic_options();
  o.predictor = ContinuationOptions::Predictor::Secant;
  Continuation cont(problem, o);
  RecordingObserver rec;
  const auto r = cont.run(problem.initial_guess(), rec);
  EXPECT_EQ(r.code, StopCode::UpperBound);
  for (const auto& n : rec.notes) std::cout << "note: " << n << "\n";
  ASSERT_EQ(rec.of_kind(PointKind::Fold).size(), 2u);
  EXPECT_NEAR(rec.of_kind(PointKind::Fold)[0]->lambda, 2.0, 1e-10);
}

// Natural continuation cannot pass a fold: beyond lambda = 2 the only solution of the cubic is
// on the other branch (u > 2), and the tangent check refuses the jump; the run ends at the
// step floor just below the fold, with the reason.
TEST(Continuation, NaturalContinuationStopsAtTheFoldWithAReason) {
  CubicProblem problem(-2.0);
  ContinuationOptions o = cubic_options();
  o.method = ContinuationOptions::Method::Natural;
  o.step.min = 1e-6;
  Continuation cont(problem, o);
  RecordingObserver rec;
  const auto r = cont.run(problem.initial_guess(), rec);
  EXPECT_EQ(r.code, StopCode::StepFloor);
  EXPECT_NE(r.reason.find("step size fell below"), std::string::npos) << r.reason;
  for (const auto& p : rec.points) {
    EXPECT_LE(p.lambda, 2.0);
    EXPECT_LT(p.u[0], -1.0 + 1e-2);  // never jumped to the other branch
  }
  EXPECT_GT(rec.points.back().lambda, 2.0 - 1e-3);  // it got close to the fold
}

TEST(Continuation, FailureStatusHalvesTheStepAndStopsWithTheReason) {
  // the band is wider than the largest parameter change one step can make, so it cannot be
  // stepped over
  auto problem = std::make_unique<test::FailingBand>(std::make_unique<Bratu1DProblem>(32, 0.0), 1.5, 2.9);
  ContinuationOptions o;
  o.parameter = "lambda";
  o.stop.upper = 3.0;
  o.step.initial = 0.2;
  o.step.max = 0.5;
  o.step.min = 1e-4;
  Continuation cont(*problem, o);
  RecordingObserver rec;
  const auto r = cont.run(problem->initial_guess(), rec);
  EXPECT_EQ(r.code, StopCode::StepFloor);
  EXPECT_NE(r.reason.find("invalid-state"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("the model breaks down here"), std::string::npos) << r.reason;
  EXPECT_FALSE(rec.rejections.empty());
  EXPECT_LT(rec.points.back().lambda, 1.5);
  EXPECT_GT(rec.points.back().lambda, 1.5 - 1e-2);  // halving crept up to the band
}

TEST(Continuation, AnOversizedStepIsHalvedUntilItWorks) {
  Bratu1DProblem problem(32, 0.0);
  ContinuationOptions o;
  o.corrector.method = CorrectorOptions::Method::Newton;  // a factorisation per corrector iteration
  o.parameter = "lambda";
  o.stop.upper = 2.0;
  o.step.initial = 50.0;  // lands far off the branch: corrector diverges or overflows
  o.step.max = 50.0;
  o.events.land_on_values = false;  // else the step is shortened to land on the bound (next test)
  Continuation cont(problem, o);
  RecordingObserver rec;
  const auto r = cont.run(problem.initial_guess(), rec);
  EXPECT_EQ(r.code, StopCode::UpperBound) << r.reason;
  EXPECT_GE(rec.rejections.size(), 1u);
  EXPECT_EQ(rec.points.back().lambda, 2.0);
  // one symbolic analysis for the whole branch, one numeric factorisation per corrector step
  const auto& lu = cont.bordered().lu().statistics();
  EXPECT_EQ(lu.analyses + lu.analyses_reused, 1);  // made here or taken from an identical one
  EXPECT_GT(lu.factorisations, 10);
}

// The same oversized step lands on the bound: shortened to it and corrected there, no step
// beyond it, the end is the step's own point.
TEST(Continuation, AStepThatWouldCrossTheBoundLandsOnIt) {
  Bratu1DProblem problem(32, 0.0);
  ContinuationOptions o;
  o.parameter = "lambda";
  o.stop.upper = 2.0;
  o.step.initial = 50.0;
  o.step.max = 50.0;
  Continuation cont(problem, o);
  RecordingObserver rec;
  const auto r = cont.run(problem.initial_guess(), rec);
  EXPECT_EQ(r.code, StopCode::UpperBound) << r.reason;
  EXPECT_TRUE(rec.rejections.empty());
  ASSERT_EQ(rec.points.size(), 2u);  // the start and the end, one step
  EXPECT_EQ(rec.points.back().kind, PointKind::End);
  EXPECT_EQ(rec.points.back().label, "upper");
  EXPECT_EQ(rec.points.back().lambda, 2.0);
  Vector F;
  problem.parameters().set("lambda", 2.0);
  ASSERT_TRUE(problem.residual(rec.points.back().u, F).is_ok());
  EXPECT_LT(F.lpNorm<Eigen::Infinity>(), 1e-9);
}

// Requested values are landed on: the same solutions as when located after the step, exactly at
// the values, in fewer corrector iterations (one correction per value instead of a step past it
// and a located one), and no step more than the branch needs.
TEST(Continuation, StepsLandOnRequestedValues) {
  auto trace = [](bool land, RecordingObserver& rec) {
    CubicProblem problem(-2.0);
    ContinuationOptions o = cubic_options();
    o.events.stops = {-1.0, 0.0, 0.5, 1.0, 1.5};
    o.events.land_on_values = land;
    return trace_from_guess(problem, o, rec);
  };
  RecordingObserver landed, located;
  const ContinuationResult r_landed = trace(true, landed), r_located = trace(false, located);
  ASSERT_EQ(r_landed.code, StopCode::UpperBound);
  ASSERT_EQ(r_located.code, StopCode::UpperBound);
  const auto a = landed.of_kind(PointKind::Requested), b = located.of_kind(PointKind::Requested);
  ASSERT_EQ(a.size(), 15u);  // each value at each of the three crossings of the S-shaped branch
  ASSERT_EQ(a.size(), b.size());

  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i]->lambda, b[i]->lambda);
    EXPECT_NEAR(a[i]->u[0], b[i]->u[0], 1e-10);
    EXPECT_NEAR(std::pow(a[i]->u[0], 3) - 3 * a[i]->u[0], a[i]->lambda, 1e-10);  // the corrector's tolerance
  }
  // (all solves, those of rejected attempts included)
  std::cout << "rows " << landed.points.size() << " landed, " << located.points.size() << " located; solves "
            << r_landed.timings.solves << " and " << r_located.timings.solves << ", rejected steps "
            << r_landed.rejected << " and " << r_located.rejected << "\n";
  EXPECT_LT(r_landed.timings.solves, r_located.timings.solves);
  EXPECT_LT(landed.points.size(), located.points.size());
  EXPECT_EQ(landed.of_kind(PointKind::Fold).size(), 2u);
}

// A landed point's bordered determinant is taken under the pseudo-arclength row like every
// other point's: under the parameter row its sign flips wherever the parameter decreases, and
// every stop on the middle (decreasing) part of the S would pass for two branch points.
TEST(Continuation, LandedStopsAreNotBranchPoints) {
  for (const bool kept : {false, true}) {
    CubicProblem problem(-2.0);
    ContinuationOptions o = cubic_options();
    o.events.stops = {-1.0, 0.0, 1.0};
    o.events.branch_points = true;
    if (kept) {
      o.corrector.method = CorrectorOptions::Method::Chord;
      o.corrector.block_elimination = true;
      o.corrector.keep = true;
    }
    Continuation cont(problem, o);
    RecordingObserver rec;
    ASSERT_EQ(cont.run(problem.initial_guess(), rec).code, StopCode::UpperBound);
    EXPECT_EQ(rec.of_kind(PointKind::Requested).size(), 9u) << "kept factorisation: " << kept;
    EXPECT_TRUE(rec.of_kind(PointKind::BranchPoint).empty()) << "kept factorisation: " << kept;
    EXPECT_EQ(rec.of_kind(PointKind::Fold).size(), 2u) << "kept factorisation: " << kept;
  }
}

// The predictor of located points: the cubic Hermite interpolant of the bracketing points and
// their tangents. A cubic curve is reproduced to rounding.
TEST(Hermite, ReproducesACubicCurveToRounding) {
  auto at = [](double s) {
    BranchPoint p;
    p.s = s;
    p.u = Vector(2);
    p.u << 1 + 2 * s - s * s * s, s * s;
    p.lambda = s + 0.5 * s * s * s;
    p.tu = Vector(2);
    p.tu << 2 - 3 * s * s, 2 * s;  // d/ds: the cubic's own derivative
    p.tlambda = 1 + 1.5 * s * s;
    return p;
  };
  const BranchPoint a = at(0.2), b = at(0.9), want = at(0.55);
  const BranchFunctional parameter = [](const Vector&, double l, bool) { return l; };
  Vector u;
  double lambda = 0, x = 0;
  ASSERT_TRUE(hermite_point(a, b, parameter, want.lambda, u, lambda, x));
  EXPECT_NEAR(x, 0.5, 1e-14);
  EXPECT_NEAR(lambda, want.lambda, 1e-14);
  EXPECT_NEAR((u - want.u).lpNorm<Eigen::Infinity>(), 0.0, 1e-14);
  // a functional of the state: where u_1 = u_1(0.55)
  const BranchFunctional second = [](const Vector& v, double, bool) { return v[1]; };
  ASSERT_TRUE(hermite_point(a, b, second, want.u[1], u, lambda, x));
  EXPECT_NEAR(lambda, want.lambda, 1e-14);
}

// On a curve that is not a cubic (the unit circle by arclength) the error falls as h^4, against
// h^2 for the chord between the two points.
TEST(Hermite, FourthOrderOnACircle) {
  const auto at = circle_point;
  const BranchFunctional parameter = [](const Vector&, double l, bool) { return l; };
  double previous = NAN, previous_chord = NAN;
  for (double h : {0.4, 0.2, 0.1, 0.05}) {
    const BranchPoint a = at(0.1), b = at(0.1 + h);
    const double target = std::sin(0.1 + 0.37 * h);
    Vector u;
    double lambda = 0, x = 0;
    ASSERT_TRUE(hermite_point(a, b, parameter, target, u, lambda, x));
    const double exact = std::sqrt(1 - target * target);
    const double error = std::abs(u[0] - exact);
    const double tau = (target - a.lambda) / (b.lambda - a.lambda);
    const double chord = std::abs(a.u[0] + tau * (b.u[0] - a.u[0]) - exact);
    if (std::isfinite(previous)) {
      std::cout << "h = " << h << ": Hermite order " << std::log2(previous / error) << ", chord order "
                << std::log2(previous_chord / chord) << "\n";
      EXPECT_NEAR(std::log2(previous / error), 4.0, 0.3);
      EXPECT_NEAR(std::log2(previous_chord / chord), 2.0, 0.3);
    }
    EXPECT_LT(error, 0.1 * chord);
    previous = error;
    previous_chord = chord;
  }
}

// Past the top of the circle the parameter does not reach the target on the segment: no point
// (the caller falls back to the chord), and nothing is written.
TEST(Hermite, NoPointWhereTheCubicMissesTheTarget) {
  const auto at = circle_point;
  const BranchFunctional parameter = [](const Vector&, double l, bool) { return l; };
  Vector u = Vector::Constant(1, 7.0);
  double lambda = 7.0, x = 7.0;
  EXPECT_FALSE(hermite_point(at(1.3), at(1.9), parameter, 1.01, u, lambda, x));
  EXPECT_EQ(u[0], 7.0);
  EXPECT_EQ(lambda, 7.0);
  BranchPoint no_tangent = at(1.9);
  no_tangent.tu.resize(0);
  EXPECT_FALSE(hermite_point(at(1.3), no_tangent, parameter, 0.95, u, lambda, x));
}

// The Problem boilerplate of the small diagonal problems below: F_i depends on u_i and one
// parameter "lambda" only; observable u0.
class DiagonalProblem : public Problem {
 public:
  DiagonalProblem(std::string name, int n, double lambda0) : name_(std::move(name)), n_(n), pattern_(n, n) {
    params_.add("lambda", lambda0, name_);
    for (int i = 0; i < n; ++i) pattern_.insert(i, i) = 0.0;
    pattern_.makeCompressed();
  }
  std::string name() const override { return name_; }
  int size() const override { return n_; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override {
    F.resize(n_);
    for (int i = 0; i < n_; ++i) F[i] = f(i, u[i], lambda());
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    for (int i = 0; i < n_; ++i) J.valuePtr()[i] = df_du(i, u[i], lambda());
    return {};
  }
  Status parameter_derivative(int, const Vector& u, Vector& dF) override {
    dF.resize(n_);
    for (int i = 0; i < n_; ++i) dF[i] = df_dlambda(i, u[i], lambda());
    return {};
  }
  std::vector<std::string> observable_names() const override { return {"u0"}; }
  Status observables(const Vector& u, std::vector<double>& v) override {
    v = {u[0]};
    return {};
  }
  SolutionFields fields(const Vector&) const override { return {}; }

 protected:
  virtual double f(int i, double u, double lambda) const = 0;
  virtual double df_du(int i, double u, double lambda) const = 0;
  virtual double df_dlambda(int i, double u, double lambda) const = 0;
  double lambda() const { return params_.value(0); }

 private:
  std::string name_;
  int n_;
  ParameterSet params_;
  SparseMatrix pattern_;
};

// F_i = (1 + lambda) d_i u_i - 1, d_i = 1 + i: u_i = 1 / ((1 + lambda) d_i). With a factorisation
// kept from lambda_b the chord contracts the error of a correction at lambda by exactly
// |1 - (1 + lambda) / (1 + lambda_b)| per iteration.
class ScaledLinear final : public DiagonalProblem {
 public:
  // scale multiplies F: its rounding floor is about 1e-16 x scale
  explicit ScaledLinear(int n, double scale = 1.0) : DiagonalProblem("scaled-linear", n, 0.0), scale_(scale) {}
  Vector initial_guess() override {
    Vector u(size());
    for (int i = 0; i < size(); ++i) u[i] = 1.0 / (1 + i);
    return u;
  }

 private:
  double f(int i, double u, double l) const override { return scale_ * ((1 + l) * (1 + i) * u - 1); }
  double df_du(int i, double, double l) const override { return scale_ * (1 + l) * (1 + i); }
  double df_dlambda(int i, double u, double) const override { return scale_ * (1 + i) * u; }
  double scale_;
};

// With the factorisation kept across steps, a requested value is located on the kept matrix while
// the chord, at its observed rate, reaches the tolerance within the iteration limit: a few more
// solves are cheaper than a factorisation. Here one step goes from lambda = 0 to 1.2 (its
// corrector renews the factorisation near 1.2) and the stop at 0.25 is corrected on it at the
// rate 1 - 1.25 / 2.2 = 0.43, which the rate rule of a step (0.25) would refuse.
TEST(Continuation, RequestedValueLocatedOnTheKeptFactorisation) {
  auto trace = [](const std::vector<double>& stops, RecordingObserver& rec) {
    ScaledLinear p(3);
    Continuation cont(p, kept_chord_options(1.2, 1.0, 30, stops));  // one step, 0 -> 1.2
    return cont.run(p.initial_guess(), rec);
  };
  RecordingObserver plain, with_stop;
  const ContinuationResult r0 = trace({}, plain);
  const ContinuationResult r1 = trace({0.25}, with_stop);
  ASSERT_EQ(r0.code, StopCode::UpperBound) << r0.reason;
  ASSERT_EQ(r1.code, StopCode::UpperBound) << r1.reason;
  ASSERT_EQ(plain.points.size(), 2u);  // start, end: one step
  const auto requested = with_stop.of_kind(PointKind::Requested);
  ASSERT_EQ(requested.size(), 1u);
  const BranchPoint& q = *requested[0];
  EXPECT_EQ(q.lambda, 0.25);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(q.u[i], 1.0 / (1.25 * (1 + i)), 1e-10);
  std::cout << "stop corrected in " << q.iterations << " chord iterations; factorisations " << r0.factorisations
            << " without the stop, " << r1.factorisations << " with it\n";
  EXPECT_GT(q.iterations, 5);  // at the rate 0.43: on the old matrix, not a fresh one
  // The predictor is the cubic Hermite interpolant of the start and the step's point: at the
  // rate 0.43 the chord needs 20 iterations from it, 25 from the straight chord between the two
  // points (whose error, 0.09 in u_0, is about 60 times the cubic's)
  EXPECT_LE(q.iterations, 22);
  EXPECT_EQ(r1.factorisations, r0.factorisations);
}

// The same with slow chords: on a factorisation kept from lambda = L the stop at v contracts by
// 1 - (1 + v) / (1 + L) per iteration, which a ratio test alone takes for the rounding floor once
// |F| is within 1e3 of the tolerance (accepted at 1e-8 to 1e-7 before). Each stop must reach the
// tolerance, on the kept factorisation or on a renewed one.
TEST(Continuation, ASlowChordAtALocatedPointIsNotTakenForRounding) {
  struct Case {
    double step;
    int max_iterations;
    std::vector<double> stops;
  };
  // rates 0.63 (stop 0.1, max 60); 0.67 with the default 10 iterations (stop 0.001); 0.82-0.83
  // (stops 0.003-0.1 after a step to 5, max 200)
  const Case cases[] = {{2.0, 60, {0.1}}, {2.0, 10, {0.001}}, {5.0, 200, {0.003, 0.01, 0.03, 0.1}}};
  for (const Case& cs : cases) {
    ScaledLinear p(3);
    Continuation cont(p, kept_chord_options(cs.step, cs.step - 0.1, cs.max_iterations, cs.stops));
    RecordingObserver rec;
    const ContinuationResult r = cont.run(p.initial_guess(), rec);
    ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
    const auto requested = rec.of_kind(PointKind::Requested);
    ASSERT_EQ(requested.size(), cs.stops.size());
    for (const BranchPoint* q : requested) {
      std::cout << "step to " << cs.step << ", stop " << q->lambda << ": " << q->iterations
                << " chord iterations to |F| = " << q->residual << "\n";
      EXPECT_LE(q->residual, 1e-10) << q->lambda;  // the tolerance (residual_tolerance 1e-10, scale 1)
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(q->u[i], 1.0 / ((1 + q->lambda) * (1 + i)), 1e-10);
    }
  }
}

// Where the tolerance lies below the residual's rounding floor (here F scaled by 1e4: |F| stalls
// near 1e-12, the tolerance is 1e-14), the points of a step stop at the floor; the chord of a
// point located between them aims at the floor they reached instead of renewing the
// factorisation for a tolerance it cannot reach: 21 stops on one step cost no factorisation (one
// of them, aiming at the tolerance, renewed it at the floor).
TEST(Continuation, ALocatedChordAimsAtTheFloorItsNeighboursReached) {
  NewtonOptions newton;
  newton.residual_tolerance = 1e-14;
  auto trace = [&](const std::vector<double>& stops, RecordingObserver& rec) {
    ScaledLinear p(3, 1e4);
    Continuation cont(p, kept_chord_options(1.2, 1.0, 30, stops), newton);
    return cont.run(p.initial_guess(), rec);
  };
  RecordingObserver plain, with_stops;
  const ContinuationResult r0 = trace({}, plain);
  std::vector<double> stops;  // rates 0.30 down to 0.12
  for (int k = 0; k < 21; ++k) stops.push_back(0.54 + 0.02 * k);
  const ContinuationResult r1 = trace(stops, with_stops);
  ASSERT_EQ(r1.code, StopCode::UpperBound) << r1.reason;
  const auto requested = with_stops.of_kind(PointKind::Requested);
  ASSERT_EQ(requested.size(), stops.size());
  for (const BranchPoint* q : requested) {
    EXPECT_LE(q->residual, 1e-11);  // within 1e3 of the tolerance
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(q->u[i], 1.0 / ((1 + q->lambda) * (1 + i)), 1e-12);
  }
  std::cout << r0.factorisations << " factorisations without the stops, " << r1.factorisations << " with them\n";
  EXPECT_EQ(r1.factorisations, r0.factorisations);
}

// A located point whose correction fails on the kept factorisation is tried once more from its
// prediction with a factorisation made there. Here the first residual at the requested value
// fails (an injected failure standing for a chord that broke down); the second attempt lands on
// it exactly. Without that attempt the value would be found by root finding along the arclength,
// to the event tolerance only.
TEST(Continuation, ALocatedCorrectionThatFailsIsRetriedWithAFreshFactorisation) {
  class FailOnceAt final : public Problem {
   public:
    explicit FailOnceAt(double value) : value_(value), inner_(3) {}
    std::string name() const override { return "fail-once"; }
    int size() const override { return inner_.size(); }
    ParameterSet& parameters() override { return inner_.parameters(); }
    const ParameterSet& parameters() const override { return inner_.parameters(); }
    const SparseMatrix& jacobian_pattern() const override { return inner_.jacobian_pattern(); }
    Status residual(const Vector& u, Vector& F) override {
      if (inner_.parameters().value(0) == value_ && !failed_) {
        failed_ = true;
        return {StatusCode::InvalidState, "injected failure"};
      }
      return inner_.residual(u, F);
    }
    Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override { return inner_.jacobian(u, F, J); }
    Status parameter_derivative(int i, const Vector& u, Vector& dF) override {
      return inner_.parameter_derivative(i, u, dF);
    }
    Vector initial_guess() override { return inner_.initial_guess(); }
    std::vector<std::string> observable_names() const override { return inner_.observable_names(); }
    Status observables(const Vector& u, std::vector<double>& v) override { return inner_.observables(u, v); }
    SolutionFields fields(const Vector& u) const override { return inner_.fields(u); }
    bool failed() const { return failed_; }

   private:
    double value_;
    ScaledLinear inner_;
    bool failed_ = false;
  };
  FailOnceAt p(0.25);
  ContinuationOptions o = kept_chord_options(0.5, 1.0, 30, {0.25});
  o.method = ContinuationOptions::Method::Arclength;  // root finding along the arclength is the fallback
  Continuation cont(p, o);
  RecordingObserver rec;
  const ContinuationResult r = cont.run(p.initial_guess(), rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  EXPECT_TRUE(p.failed());
  const auto requested = rec.of_kind(PointKind::Requested);
  ASSERT_EQ(requested.size(), 1u);
  EXPECT_EQ(requested[0]->lambda, 0.25);  // exactly: the fixed-parameter corrector, not root finding
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(requested[0]->u[i], 1.0 / (1.25 * (1 + i)), 1e-10);
}

TEST(Continuation, BadOptionsAreRejected) {
  CubicProblem problem(0.0);
  ContinuationOptions o = cubic_options();
  o.parameter = "mu";
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o = cubic_options();
  o.stop.lower = 1;
  o.stop.upper = 0;
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o = cubic_options();
  o.stop.observable = "v";
  o.stop.above = 1;
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o = cubic_options();
  o.step.shrink = 1.0;  // a failed step must shrink
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o = cubic_options();
  o.step.target_iterations = 12;  // above Newton's limit of 10
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o.corrector.max_iterations = 12;
  EXPECT_NO_THROW(Continuation(problem, o));
  o = cubic_options();
  o.corrector.renewal_cost = -1.0;
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
}

// A chord on a kept factorisation that needs more iterations than the target while it contracts
// well (many decades at a good rate) keeps its factorisation: renewing it at the new point made
// the next step's chord no faster. On u_i = 1 / ((1 + lambda)(1 + i)) a factorisation made at
// lambda0 contracts by (lambda - lambda0) / (1 + lambda0): with steps of 0.25 the rate passes 0.25
// on the second step after each renewal, so the branch 0 -> 2 needs a renewal every second step.
TEST(Continuation, AGoodChordSlowerThanTheTargetKeepsItsFactorisation) {
  ScaledLinear p(3);
  ContinuationOptions o = kept_chord_options(0.25, 2.0, 30, {});
  Continuation cont(p, o);
  RecordingObserver rec;
  const ContinuationResult r = cont.run(p.initial_guess(), rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  int slow = 0;
  for (const BranchPoint& q : rec.points) slow += q.iterations > o.target_iterations();
  std::cout << rec.points.size() << " rows, " << slow << " over the target, " << r.factorisations
            << " factorisations\n";
  EXPECT_GT(slow, 2);  // the case this is about
  EXPECT_LE(r.factorisations, 1 + (static_cast<int>(rec.points.size()) - 1 + 1) / 2);
}

// renewal_cost: a step's chord slower than chord_rate goes on where it needs fewer solves than a
// factorisation costs. On the same branch as above the renewals fall, every point still solves
// its equations to the tolerance.
TEST(Continuation, ACostedChordGoesOnInsteadOfRenewing) {
  auto trace = [](double renewal_cost, RecordingObserver& rec) {
    ScaledLinear p(3);
    ContinuationOptions o = kept_chord_options(0.25, 2.0, 30, {});
    o.corrector.renewal_cost = renewal_cost;
    return trace_from_guess(p, o, rec);
  };
  RecordingObserver by_rate, by_cost;
  const ContinuationResult r0 = trace(0.0, by_rate), r1 = trace(25.0, by_cost);
  ASSERT_EQ(r0.code, StopCode::UpperBound) << r0.reason;
  ASSERT_EQ(r1.code, StopCode::UpperBound) << r1.reason;
  std::cout << "factorisations: " << r0.factorisations << " by the rate rule, " << r1.factorisations
            << " with renewal_cost = 25\n";
  EXPECT_LT(r1.factorisations, r0.factorisations);
  ASSERT_EQ(by_cost.points.size(), by_rate.points.size());  // the same steps
  for (const BranchPoint& q : by_cost.points)
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(q.u[i], 1.0 / ((1 + q.lambda) * (1 + i)), 1e-10) << q.lambda;
}

// A costed chord falls slowly, which near the tolerance a ratio test takes for the rounding
// floor (as at located points). Steps of 0.6 on matrices kept from lambda0 contract by
// (lambda - lambda0) / (1 + lambda0) per iteration: 0.6 on the first step, up to 0.75 later.
// Every point must still reach the tolerance (|F| <= 1e-10 here), not just come near it.
TEST(Continuation, ASlowCostedChordIsNotTakenForRounding) {
  ScaledLinear p(3);
  ContinuationOptions o = kept_chord_options(0.6, 2.3, 200, {});
  o.corrector.renewal_cost = 1000;  // never renewed while the chord converges
  Continuation cont(p, o);
  RecordingObserver rec;
  const ContinuationResult r = cont.run(p.initial_guess(), rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  std::cout << r.factorisations << " factorisations for " << rec.points.size() << " rows; iterations";
  for (const BranchPoint& q : rec.points) std::cout << " " << q.iterations;
  std::cout << "\n";
  for (const BranchPoint& q : rec.points) {
    EXPECT_LE(q.residual, 1e-10) << "lambda = " << q.lambda;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(q.u[i], 1.0 / ((1 + q.lambda) * (1 + i)), 1e-10) << q.lambda;
  }
  EXPECT_GE(rec.points[1].iterations, 20);  // the slow chord this is about: 0.6 per iteration
}

// The upper bound ends a branch that leaves the interval upwards, the lower one a branch that
// leaves it downwards; a branch that starts below the lower bound and rises through it goes on
// (as when the bound is located after the step): landing must not end it there.
TEST(Continuation, ABoundApproachedFromOutsideIsNotLandedOn) {
  auto trace = [](bool land, RecordingObserver& rec) {
    CubicProblem problem(-2.0);
    ContinuationOptions o = cubic_options();
    o.stop.lower = -1.0;  // the start, lambda = -2, lies below it
    o.events.land_on_values = land;
    Continuation cont(problem, o);
    return cont.run(problem.initial_guess(), rec);
  };
  RecordingObserver landed, located;
  const ContinuationResult a = trace(true, landed), b = trace(false, located);
  EXPECT_EQ(a.code, b.code) << a.reason << " / " << b.reason;
  ASSERT_FALSE(landed.points.empty());
  EXPECT_EQ(landed.points.back().lambda, located.points.back().lambda);
  EXPECT_EQ(landed.points.back().label, located.points.back().label);
  // the same crossing: the one on the way down (u = 0.35), not the first one (u = -1.88)
  EXPECT_NEAR(landed.points.back().u[0], located.points.back().u[0], 1e-9);
}

// A stop where the problem cannot be solved: the landing fails, the step's retries are ordinary
// steps and the branch goes on past it (the stop reported as not located), as it does without
// landing; before, the same landing was retried at every halving until the step floor.
TEST(Continuation, AFailedLandingDoesNotEndTheBranch) {
  for (const bool land : {true, false}) {
    // u^3 - 3u = lambda with no residual for lambda in [2.9999, 3.0001]
    test::FailingBand problem(std::make_unique<CubicProblem>(-2.0), 2.9999, 3.0001);
    ContinuationOptions o = cubic_options();
    o.step.initial = 0.5;
    o.step.max = 0.5;
    o.events.stops = {3.0};
    o.events.land_on_values = land;
    Continuation cont(problem, o);
    RecordingObserver rec;
    const ContinuationResult r = cont.run(problem.initial_guess(), rec);
    EXPECT_EQ(r.code, StopCode::UpperBound) << "landing " << land << ": " << r.reason;
    EXPECT_TRUE(rec.of_kind(PointKind::Requested).empty()) << "landing " << land;
  }
}

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
