// The cubic Hermite curve through two points of a branch and their tangents: as the predictor of
// located points between them (interpolation) and as the cubic predictor of the next step beyond
// them (extrapolation, Predictor::bend and its policy use_cubic).
#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <optional>

#include "continuation/Continuation.hpp"
#include "continuation/engine/Hermite.hpp"
#include "continuation/engine/Predictor.hpp"
#include "support/ContinuationTestSupport.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using namespace keller::test;

namespace {

// A point of the cubic curve u = (1 + 2s - s^3, s^2), lambda = s + s^3 / 2, with its derivative in
// s as the tangent.
BranchPoint cubic_curve_point(double s) {
  BranchPoint p;
  p.s = s;
  p.u = Vector(2);
  p.u << 1 + 2 * s - s * s * s, s * s;
  p.lambda = s + 0.5 * s * s * s;
  p.tu = Vector(2);
  p.tu << 2 - 3 * s * s, 2 * s;
  p.tlambda = 1 + 1.5 * s * s;
  return p;
}

}  // namespace

// The predictor of located points: the cubic Hermite interpolant of the bracketing points and
// their tangents. A cubic curve is reproduced to rounding.
TEST(Hermite, ReproducesACubicCurveToRounding) {
  const auto at = cubic_curve_point;
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

// The cubic continued beyond its second point (the cubic predictor): a cubic curve exactly, and the
// parameter's value found on it; on the circle by arclength the prediction's error falls as h^4
// (a step as long as the base: s = b.s + h), against h^2 for the tangent's straight line.
TEST(Hermite, ExtrapolatesACubicExactlyAndACircleAtFourthOrder) {
  const auto at = cubic_curve_point;
  const BranchPoint a = at(0.2), b = at(0.5), want = at(1.1);
  Vector u;
  double lambda = 0;
  ASSERT_TRUE(hermite_extrapolate(a, b, 0.6, u, lambda));
  EXPECT_NEAR((u - want.u).lpNorm<Eigen::Infinity>(), 0.0, 1e-13);
  EXPECT_NEAR(lambda, want.lambda, 1e-13);
  const BranchFunctional parameter = [](const Vector&, double l, bool) { return l; };
  const std::optional<double> sigma = hermite_extrapolate_to(a, b, parameter, want.lambda, 0.3);  // from a guess
  ASSERT_TRUE(sigma.has_value());
  EXPECT_NEAR(*sigma, 0.6, 1e-13);
  double previous = NAN, previous_line = NAN;
  for (double h : {0.2, 0.1, 0.05, 0.025}) {
    const BranchPoint p = circle_point(0.3), c = circle_point(0.3 + h), exact = circle_point(0.3 + 2 * h);
    ASSERT_TRUE(hermite_extrapolate(p, c, h, u, lambda));
    const double error = std::hypot(u[0] - exact.u[0], lambda - exact.lambda);
    const double line = std::hypot(c.u[0] + h * c.tu[0] - exact.u[0], c.lambda + h * c.tlambda - exact.lambda);
    if (std::isfinite(previous)) {
      EXPECT_NEAR(std::log2(previous / error), 4.0, 0.3);
      EXPECT_NEAR(std::log2(previous_line / line), 2.0, 0.3);
    }
    EXPECT_LT(error, 0.1 * line);
    previous = error;
    previous_line = line;
  }
  BranchPoint no_tangent = circle_point(0.5);
  no_tangent.tu.resize(0);
  EXPECT_FALSE(hermite_extrapolate(circle_point(0.3), no_tangent, 0.1, u, lambda));
  EXPECT_FALSE(hermite_extrapolate_to(circle_point(0.3), no_tangent, parameter, 0.5, 0.1).has_value());
  // where the continued cubic takes a value, on curves that are not cubics, for parameters of size 1
  // and 100 and bases of 0.1 and 1e-3: found every time, to 1e-12 of the values (Newton's step
  // near the root is rounding, which a test on the step alone took for no convergence)
  for (double size : {1.0, 100.0})
    for (double h : {0.1, 1e-3})
      for (int k = 0; k < 50; ++k) {
        const double s0 = 0.024 * k;  // (below the circle's top, where lambda = sin s has a maximum)
        BranchPoint p = circle_point(s0), q = circle_point(s0 + h);
        for (BranchPoint* x : {&p, &q}) x->lambda = size * (1.0 + x->lambda), x->tlambda *= size;
        const double target = size * (1.0 + std::sin(s0 + 1.7 * h));
        const std::optional<double> found = hermite_extrapolate_to(p, q, parameter, target, 0.5 * h);
        ASSERT_TRUE(found.has_value()) << "size " << size << ", h " << h << ", s0 " << s0;
        ASSERT_TRUE(hermite_extrapolate(p, q, *found, u, lambda));
        EXPECT_LE(std::abs(lambda - target), 1e-12 * std::abs(target));
      }
}

// The cubic predictor at a landing on a stop: on the unit circle (parametrised by the arclength
// of the norm, wu = wl = 1/2), a step from s = 0.5 whose straight prediction crosses lambda =
// sin(0.56) lands there, and bend puts the state on the cubic where it takes that value: the
// parameter exactly the stop's, the state within 1e-5 of the circle's (2.5e-6: a step of 0.06 to
// the fourth), the straight line's more than 1e-3 off.
TEST(Predictor, TheCubicPredictsALandingOnAStopOnTheBranch) {
  const double r2 = std::sqrt(2.0);
  const auto at = [&](double t) {  // t: the angle; s = t / sqrt(2) in the norm
    BranchPoint p;
    p.s = t / r2;
    p.u = Vector::Constant(1, std::cos(t));
    p.lambda = std::sin(t);
    p.tu = Vector::Constant(1, -r2 * std::sin(t));
    p.tlambda = r2 * std::cos(t);
    return p;
  };
  ContinuationOptions o;
  o.parameter = "lambda";
  o.predictor = ContinuationOptions::Predictor::Cubic;
  const double stop = std::sin(0.56);
  o.events.stops = {stop};
  const ArclengthNorm norm(1, 1.0, 0.5);
  const Predictor predictor(o, norm);
  const BranchPoint prev = at(0.44), cur = at(0.5);
  ASSERT_NEAR(norm.norm(cur.tu, cur.tlambda), 1.0, 1e-14);
  Prediction p = predictor.predict(cur, &prev, cur.tu, cur.tlambda, 0.08 / r2, true);
  ASSERT_TRUE(p.land.has_value());
  ASSERT_EQ(p.land->value, stop);
  const double exact = std::cos(0.56), straight = std::abs(p.u[0] - exact);
  predictor.bend(cur, prev, cur.tu, cur.tlambda, p);
  EXPECT_EQ(p.lambda, stop);
  EXPECT_LT(std::abs(p.u[0] - exact), 1e-5);
  EXPECT_GT(straight, 1e-3);
  // a tangent predictor leaves it on the straight line
  o.predictor = ContinuationOptions::Predictor::Tangent;
  Prediction q = predictor.predict(cur, &prev, cur.tu, cur.tlambda, 0.08 / r2, true);
  predictor.bend(cur, prev, cur.tu, cur.tlambda, q);
  EXPECT_NEAR(std::abs(q.u[0] - exact), straight, 1e-15);
}

// The cubic predictor on the fold problem with Newton's corrector and steps of at most 0.15: the
// same folds to 1e-10 with fewer corrector iterations per point than the tangent's straight line
// (each iteration of Newton there is one factorisation).
TEST(Continuation, TheCubicPredictorStartsTheCorrectorCloser) {
  auto trace = [](ContinuationOptions::Predictor predictor, RecordingObserver& rec) {
    CubicProblem problem(-2.0);
    ContinuationOptions o = cubic_options();
    o.predictor = predictor;
    o.step.initial = o.step.max = 0.15;
    Continuation cont(problem, o);
    return cont.run(problem.initial_guess(), rec);
  };
  RecordingObserver line, cubic;
  const ContinuationResult r0 = trace(ContinuationOptions::Predictor::Tangent, line);
  const ContinuationResult r1 = trace(ContinuationOptions::Predictor::Cubic, cubic);
  ASSERT_EQ(r0.code, StopCode::UpperBound);
  ASSERT_EQ(r1.code, StopCode::UpperBound);
  for (const RecordingObserver* rec : {&line, &cubic}) {
    ASSERT_EQ(rec->of_kind(PointKind::Fold).size(), 2u);
    EXPECT_NEAR(rec->of_kind(PointKind::Fold)[0]->lambda, 2.0, 1e-10);
    EXPECT_NEAR(rec->of_kind(PointKind::Fold)[1]->lambda, -2.0, 1e-10);
  }
  auto iterations = [](const RecordingObserver& rec) {
    int n = 0, points = 0;
    for (const BranchPoint& p : rec.points)
      if (p.kind == PointKind::Regular) n += p.iterations, ++points;
    return static_cast<double>(n) / std::max(points, 1);
  };
  std::cout << "corrector iterations per regular point: tangent " << iterations(line) << ", cubic " << iterations(cubic)
            << "\n";
  EXPECT_LT(iterations(cubic), iterations(line));
}

// Where the predictor follows the cubic: a tangent that turned little over the last step, a
// prediction ahead and within twice the last step.
TEST(Predictor, TheCubicWhereTheBranchBendsLittleAndNotFarBeyondItsBase) {
  EXPECT_TRUE(use_cubic(3.0, 0.1, 0.1));
  EXPECT_TRUE(use_cubic(kCubicMaxTurn, 2.0, 1.0));
  EXPECT_FALSE(use_cubic(27.0, 0.1, 0.1));  // the tangent turned fast
  EXPECT_FALSE(use_cubic(3.0, 0.21, 0.1));  // beyond twice the base
  EXPECT_FALSE(use_cubic(3.0, -0.1, 0.1));  // behind
  EXPECT_FALSE(use_cubic(3.0, 0.1, 0.0));   // no base
}
