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
#include "problems/Bratu1DProblem.hpp"
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

ContinuationOptions cubic_options() {
  ContinuationOptions o;
  o.parameter = "lambda";
  o.lower = -5.0;
  o.upper = 5.0;
  o.initial_step = 0.1;
  o.max_step = 0.3;
  o.event_tolerance = 1e-12;
  return o;
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
  o.event_tolerance = 1e-11;
  Continuation cont(problem, o);
  RecordingObserver rec;
  cont.run(problem.initial_guess(), rec);
  const auto events = rec.of_kind(PointKind::Event);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0]->label, "u - 1/2");
  std::cout << "event u = 1/2 located at lambda = " << events[0]->lambda << " (exact -1.375)\n";
  EXPECT_NEAR(events[0]->lambda, -1.375, o.event_tolerance);
  EXPECT_NEAR(events[0]->u[0], 0.5, 1e-9);
}

TEST(Continuation, RequestedValuesAtEveryCrossing) {
  CubicProblem problem(-2.0);
  ContinuationOptions o = cubic_options();
  o.stops = {0.0, 1.0};
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
  o.min_step = 1e-6;
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
  o.upper = 3.0;
  o.initial_step = 0.2;
  o.max_step = 0.5;
  o.min_step = 1e-4;
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
  o.parameter = "lambda";
  o.upper = 2.0;
  o.initial_step = 50.0;  // lands far off the branch: corrector diverges or overflows
  o.max_step = 50.0;
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

TEST(Continuation, BadOptionsAreRejected) {
  CubicProblem problem(0.0);
  ContinuationOptions o = cubic_options();
  o.parameter = "mu";
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o = cubic_options();
  o.lower = 1;
  o.upper = 0;
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o = cubic_options();
  o.stop_observable = "v";
  o.stop_above = 1;
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o = cubic_options();
  o.reuse_factorisation = true;  // needs the chord corrector and block elimination
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o.corrector = ContinuationOptions::Corrector::Chord;
  EXPECT_THROW(Continuation(problem, o), std::invalid_argument);
  o.block_elimination = true;
  EXPECT_NO_THROW(Continuation(problem, o));
}
