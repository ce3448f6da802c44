// The continuation engine with the chord on a kept factorisation: located points on it, the
// renewal policy and its cost, landing on bounds and stops.
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
