// The continuation engine on problems with known answers: the bordered solve, folds and events
// located to tight tolerances, requested values hit exactly, natural continuation stopping at a
// fold, steps landing on values, numerical failures handled by step halving.
#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>

#include "continuation/Continuation.hpp"
#include "continuation/engine/BorderedSystem.hpp"
#include "core/ConvergenceTest.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "support/ContinuationTestSupport.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using namespace keller::test;

// Both ways of solving the bordered system (the whole matrix, and block elimination on J with
// its fallback to the whole matrix) against a dense solve, with each sparse LU, for three J:
// regular; of rank n - 1 by its values (a row the sum of two others, like J at a fold), which
// in floating point leaves J's LU a pivot of rounding size, so that the block solution either
// meets its residual test or falls back (which one depends on the LU's scaling and pivot order:
// UMFPACK falls back, MUMPS does not); and singular by its pattern (an empty column), which every
// LU reports, so that the block elimination must fall back. Either way the solution and the sign
// of the determinant are the dense ones.
TEST(BorderedSystem, MatchesDenseSolveIncludingAtAFold) {
  enum class Kind { Regular, RankDeficient, EmptyColumn };
  std::vector<SparseLUOptions::Backend> backends = {SparseLUOptions::Backend::Umfpack};
  if (mumps_available()) backends.push_back(SparseLUOptions::Backend::Mumps);
  for (auto backend : backends)
    for (auto mode : {BorderedSystem::Mode::Full, BorderedSystem::Mode::Block})
      for (Kind kind : {Kind::Regular, Kind::RankDeficient, Kind::EmptyColumn}) {
        SCOPED_TRACE(std::string(mode == BorderedSystem::Mode::Full ? "full, " : "block, ") + to_string(backend) +
                     ", J " + std::to_string(static_cast<int>(kind)));
        SparseLUOptions lu_options;
        lu_options.backend = backend;
        const int n = 12;
        SparseMatrix J = random_matrix(n, 3, kind == Kind::RankDeficient);
        if (kind == Kind::EmptyColumn) {
          J.prune([](int, int col, double) { return col != 5; });
          J.makeCompressed();
        }
        const Vector b = Vector::LinSpaced(n, 1.0, 2.0), c = Vector::LinSpaced(n, -1.0, 0.5), f = Vector::Ones(n);
        const double d = 0.3, g = -0.7;
        BorderedSystem bs(J, lu_options, mode);
        bs.set(J, b, c, d);
        ASSERT_TRUE(bs.factorize().is_ok());
        Vector x;
        double y = 0;
        ASSERT_TRUE(bs.solve(f, g, x, y).is_ok());
        if (mode == BorderedSystem::Mode::Block) {
          if (kind == Kind::Regular) {
            EXPECT_EQ(bs.fallbacks(), 0);
          } else if (kind == Kind::RankDeficient) {
            EXPECT_LE(bs.fallbacks(), 1);
          } else {
            EXPECT_EQ(bs.fallbacks(), 1);
          }
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

// An adopted factorisation belongs to its maker: the next factorisation is made in the system's
// own object and leaves the maker's as it was. One its maker has let go of (the system holds the
// only reference: a run handed it over) is refactorised in place, with its symbolic analysis; its
// earlier factorisation is not counted as the system's.
TEST(BorderedSystem, AnAdoptedFactorisationLetGoOfIsRefactorisedAsItsOwn) {
  const int n = 12;
  const SparseMatrix J1 = random_matrix(n, 3, false);
  SparseMatrix J2 = J1;
  J2.coeffs() *= 1.5;
  const Vector b = Vector::LinSpaced(n, 1.0, 2.0), c = Vector::LinSpaced(n, -1.0, 0.5), f = Vector::Ones(n);
  const double d = 0.3, g = -0.7;
  for (bool let_go : {false, true}) {
    SCOPED_TRACE(let_go ? "let go of" : "kept by its maker");
    auto lu = std::make_shared<SparseLU>();
    ASSERT_TRUE(lu->factorize(J1).is_ok());
    SparseLU* const made = lu.get();
    BorderedSystem bs(J1, {}, BorderedSystem::Mode::Block);
    ASSERT_TRUE(bs.adopt(lu, J1, b, c, d).is_ok());
    if (let_go) lu.reset();
    bs.set(J2, b, c, d);
    ASSERT_TRUE(bs.factorize().is_ok());
    EXPECT_EQ(bs.inner_lu().get() == made, let_go);
    EXPECT_EQ(made->statistics().analyses + made->statistics().analyses_reused, 1);
    EXPECT_EQ(bs.totals().factorisations, 1);  // the system's own, not the maker's
    Vector x;
    double y = 0;
    ASSERT_TRUE(bs.solve(f, g, x, y).is_ok());
    expect_dense_solution(J2, b, c, d, f, g, x, y, bs.determinant_sign());
    if (!let_go) {  // the maker's factorisation is still J1's
      Vector x1;
      ASSERT_TRUE(lu->solve(f, x1).is_ok());
      EXPECT_LT((J1 * x1 - f).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_EQ(made->statistics().factorisations, 1);
    } else {
      EXPECT_EQ(made->statistics().factorisations, 2);
    }
  }
}

// A problem with a border of its own (an augmented problem: K bordered by m = 2 dense columns and
// rows): all borders, the problem's and the continuation's row, eliminated together on K's
// factorisation give the dense solution and the sign of the whole determinant, also after a new
// border row without refactorising; a singular K (J on a fold curve, or at a fold-Hopf point of a
// Hopf curve) falls back to the whole matrix.
TEST(BorderedSystem, ProblemBordersEliminatedOnTheInnerFactorisation) {
  const int nk = 12, m = 2, n = nk + m;
  for (bool singular : {false, true}) {
    SCOPED_TRACE(singular ? "singular K" : "regular K");
    BorderedJacobian A;
    A.K = random_matrix(nk, 5, singular);
    A.B.resize(nk, m);
    A.C.resize(nk, m);
    for (int i = 0; i < nk; ++i)
      for (int b = 0; b < m; ++b) {
        A.B(i, b) = std::sin(1.0 + i + 3.0 * b);
        A.C(i, b) = std::cos(2.0 + 0.5 * i + b);
      }
    A.D.resize(m, m);
    A.D << 0.4, -0.2, 0.3, 0.9;
    const Vector b = Vector::LinSpaced(n, 1.0, 2.0), c = Vector::LinSpaced(n, -1.0, 0.5), f = Vector::Ones(n);
    const double d = 0.3, g = -0.7;
    BorderedSystem bs(A.K, m, {}, BorderedSystem::Mode::Block);
    bs.set(A, b, c, d);
    ASSERT_TRUE(bs.factorize().is_ok());
    EXPECT_EQ(bs.fallbacks(), singular ? 1 : 0);
    Vector x;
    double y = 0;
    ASSERT_TRUE(bs.solve(f, g, x, y).is_ok());
    expect_dense_solution(A.assembled(), b, c, d, f, g, x, y, bs.determinant_sign());
    if (singular) continue;
    const Vector c2 = Vector::LinSpaced(n, 0.2, -0.9);
    const double d2 = -1.1;
    ASSERT_TRUE(bs.set_row(c2, d2).is_ok());
    ASSERT_TRUE(bs.solve(f, g, x, y).is_ok());
    EXPECT_EQ(bs.fallbacks(), 0);
    expect_dense_solution(A.assembled(), b, c2, d2, f, g, x, y, bs.determinant_sign());
    EXPECT_EQ(bs.j_factorisation(), nullptr);  // K is not the problem's Jacobian
  }
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

// A branch that cannot start ends as StartFailed (a failure, like the step floor: exit code 1),
// its reason saying so, with no point: from a first state where J fails (no tangent), from a
// stored point where J fails (a restart), from a branch point where J fails (a switch).
TEST(Continuation, ABranchThatCannotStartEndsAsStartFailed) {
  auto problem = std::make_unique<test::FailingBand>(std::make_unique<Bratu1DProblem>(32, 0.0), 1.5, 2.9);
  ContinuationOptions o;
  o.parameter = "lambda";
  o.stop.upper = 3.0;
  o.state_scale = 1.0;
  problem->parameters().set("lambda", 2.0);
  Continuation cont(*problem, o);
  BranchPoint stored;
  stored.u = Vector::Zero(problem->size());
  stored.lambda = 2.0;
  stored.tu = Vector::Zero(problem->size());
  stored.tlambda = 1.0;
  const struct {
    std::string why;
    std::function<ContinuationResult(RecordingObserver&)> start;
  } starts[] = {
      {"no tangent at the starting point", [&](RecordingObserver& rec) { return cont.run(stored.u, rec); }},
      {"the starting point cannot be evaluated", [&](RecordingObserver& rec) { return cont.resume(stored, rec); }},
      {"no branch to switch to", [&](RecordingObserver& rec) { return cont.switch_branch(stored, 1, rec); }},
  };
  for (const auto& s : starts) {
    RecordingObserver rec;
    const ContinuationResult r = s.start(rec);
    EXPECT_EQ(r.code, StopCode::StartFailed) << s.why;
    EXPECT_TRUE(is_failure(r.code));
    EXPECT_EQ(r.reason, "the branch could not start: " + s.why + ": invalid-state: the model breaks down here");
    EXPECT_TRUE(rec.points.empty()) << s.why;
    EXPECT_EQ(r.points, 0) << s.why;
  }
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
