// The continuation engine with the chord on a kept factorisation: located points on it, the
// renewal policy and its cost, Anderson mixing, Deuflhard's test, the rounding floor, restarts
// from located points, and branch points found without a factorisation at every point.
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
#include "support/ContinuationTestSupport.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using namespace keller::test;

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
