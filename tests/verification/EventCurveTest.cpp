// Event curves (continuation/EventCurveProblem): the zero of a monitor that is a minimum over
// places, continued in a second parameter, following the place of the minimum and switching
// where it moves, on a problem whose curve is known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "continuation/Continuation.hpp"
#include "continuation/EventCurveProblem.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

// F_0 = u0 + u0^3 / 3 - (1 - a + b), F_1 = u1 + u1^3 / 3 - (1 - a - b); the monitor "min u" is the
// minimum over the two places u0, u1. Its zero as a rises: u0 = 0 at a = 1 + b for b < 0, u1 = 0 at
// a = 1 - b for b > 0: the event curve a = 1 - |b|, whose minimum moves from place 0 to place 1 at
// b = 0 (a kink of the curve in (a, b)). The places' gradients are the default differences.
class TwoPlaceProblem final : public Problem {
 public:
  TwoPlaceProblem(double a, double b) : pattern_(2, 2) {
    params_.add("a", a, "load");
    params_.add("b", b, "asymmetry");
    pattern_.insert(0, 0) = 0.0;
    pattern_.insert(1, 1) = 0.0;
    pattern_.makeCompressed();
  }
  std::string name() const override { return "two-place"; }
  int size() const override { return 2; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override {
    const double a = params_.value(0), b = params_.value(1);
    F.resize(2);
    F[0] = u[0] + u[0] * u[0] * u[0] / 3.0 - (1.0 - a + b);
    F[1] = u[1] + u[1] * u[1] * u[1] / 3.0 - (1.0 - a - b);
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    J.coeffRef(0, 0) = 1.0 + u[0] * u[0];
    J.coeffRef(1, 1) = 1.0 + u[1] * u[1];
    return {};
  }
  Status parameter_derivative(int p, const Vector&, Vector& dF) override {
    dF = p == 0 ? Vector::Ones(2) : Vector(Eigen::Vector2d(-1.0, 1.0));
    return {};
  }
  Vector initial_guess() override { return Vector::Ones(2); }
  std::vector<std::string> monitor_names() const override { return {"min u"}; }
  Status monitors(const Vector& u, std::vector<double>& v) override {
    v = {std::min(u[0], u[1])};
    return {};
  }
  Status monitor_places(int, const Vector& u, std::vector<double>& v) override {
    v = {u[0], u[1]};
    return {};
  }
  SolutionFields fields(const Vector&) const override { return {}; }

 private:
  ParameterSet params_;
  SparseMatrix pattern_;
};

// F = u + u^3 / 3 + b^2 - a with the monitor "u": its zero is the event curve a = b^2, which
// turns in a (the unknown p1 of the curve) at b = 0, a minimum.
test::FunctionProblem parabola(double a, double b) {
  test::FunctionProblem p(
      "parabola", 1, {{"a", a}, {"b", b}},
      [](const Vector& u, const Vector& q) {
        return Vector::Constant(1, u[0] + u[0] * u[0] * u[0] / 3.0 + q[1] * q[1] - q[0]);
      },
      [](const Vector& u, const Vector&) { return Eigen::MatrixXd::Constant(1, 1, 1.0 + u[0] * u[0]); },
      [](int k, const Vector&, const Vector& q) { return Vector::Constant(1, k == 0 ? -1.0 : 2.0 * q[1]); });
  p.set_monitors({"u"}, [](const Vector& u) { return std::vector<double>{u[0]}; });
  return p;
}

// The curves below in b up to 0.5, with short steps and events located to 1e-10.
ContinuationOptions in_b_to_half() {
  ContinuationOptions o;
  o.parameter = "b";
  o.stop.upper = 0.5;
  o.step.initial = 0.05;
  o.step.max = 0.1;
  o.events.tolerance = 1e-10;
  return o;
}

}  // namespace

// The event curve a = b^2 from b = -0.5 to 0.5: every point on it to 1e-10, and its turn in a
// (the unknown p1: the tangent's a part changes sign) located at b = 0 to 1e-10 and labelled
// "a min", with a = b^2 = 0 there; no switch (one place).
TEST(EventCurve, TurnsInTheUnknownParameterAreLocated) {
  test::FunctionProblem p = parabola(0.25, -0.5);
  EventCurveProblem curve(p, "a", "u");
  Vector U = curve.state(Vector::Constant(1, 1e-3), 0.25 + 1e-3);
  NewtonOptions tight;
  tight.residual_tolerance = 1e-12;  // two orders below what the curve is checked to
  ASSERT_TRUE(curve.start(U, tight).is_ok());
  const ContinuationOptions o = in_b_to_half();
  test::RecordingObserver rec;
  const ContinuationResult r = curve.trace(o, tight, {}, U, rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  for (const BranchPoint& q : rec.points) EXPECT_NEAR(q.u[1], q.lambda * q.lambda, 1e-10) << "b = " << q.lambda;
  std::vector<const BranchPoint*> turns;
  for (const BranchPoint* e : rec.of_kind(PointKind::Event)) {
    EXPECT_NE(e->label, "switch");
    if (e->label == "a min") turns.push_back(e);
  }
  ASSERT_EQ(turns.size(), 1u);
  EXPECT_NEAR(turns[0]->lambda, 0.0, 1e-10);
  EXPECT_NEAR(turns[0]->u[1], 0.0, 1e-10);
  EXPECT_TRUE(rec.of_kind(PointKind::Fold).empty());  // the curve does not turn in b
}

// From the event at b = -0.5 (a = 0.5, u0 = 0) to b = 0.5: every point on a = 1 - |b| to 1e-10
// with the followed value the minimum (margin >= 0) and the monitor zero; one switch, at b = 0 to
// 1e-10 (the location tolerance), from place 0 to place 1.
TEST(EventCurve, MinimumOverPlacesFollowsItsPlaceAndSwitches) {
  TwoPlaceProblem p(0.5, -0.5);
  EventCurveProblem curve(p, "a", "min u");
  Vector U = curve.state(Eigen::Vector2d(0.01, 0.5), 0.52);
  NewtonOptions tight;
  tight.residual_tolerance = 1e-12;  // two orders below what the curve is checked to
  ASSERT_TRUE(curve.start(U, tight).is_ok());
  EXPECT_EQ(curve.place(), 0);
  EXPECT_NEAR(U[2], 0.5, 1e-12);
  const ContinuationOptions o = in_b_to_half();
  test::RecordingObserver rec;
  const ContinuationResult r = curve.trace(o, tight, {}, U, rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  const int a = static_cast<int>(curve.observable_names().size()) - 3, place = a + 1, margin = a + 2;
  int switches = 0;
  double switch_seconds = -1;
  for (size_t i = 0; i < rec.points.size(); ++i) {
    const BranchPoint& q = rec.points[i];
    EXPECT_EQ(q.index, static_cast<int>(i));  // one branch, rows in order
    const double b = q.lambda;
    EXPECT_NEAR(q.observables[a], 1.0 - std::abs(b), 1e-10) << "b = " << b;
    EXPECT_GE(q.observables[margin], -1e-10) << "b = " << b;
    std::vector<double> m;
    ASSERT_TRUE(p.monitors(q.u.head(2), m).is_ok());
    EXPECT_NEAR(m[0], 0.0, 1e-10) << "b = " << b;  // the monitor whose zero the curve is
    EXPECT_EQ(q.monitors.size(), 1u);              // only the switch margin's stop: the curve's own monitor is left out
    if (switch_seconds >= 0) {
      EXPECT_GT(q.seconds, switch_seconds);  // the wall time of the whole curve
    }
    if (q.kind == PointKind::Event && q.label == "switch") {
      ++switches;
      switch_seconds = q.seconds;
      EXPECT_NEAR(b, 0.0, 1e-10);
      EXPECT_NEAR(q.observables[a], 1.0, 1e-10);
      EXPECT_EQ(q.observables[place], 0.0);  // the row ends the piece on place 0
    } else {
      EXPECT_EQ(q.observables[place], b < 0 ? 0.0 : 1.0) << "b = " << b;
    }
    if (i > 0) {
      EXPECT_GT(q.s, rec.points[i - 1].s);
    }
  }
  EXPECT_EQ(switches, 1);
  EXPECT_NEAR(rec.points.back().lambda, 0.5, 1e-12);
  EXPECT_EQ(curve.place(), 1);
  std::cout << rec.points.size() << " points; " << r.reason << "\n";
}
