// Event curves (continuation/curves/EventCurveProblem, traced by EventCurveTracer): the zero of a
// monitor that is a minimum over places, continued in a second parameter, following the place of
// the minimum and switching where it moves, on a problem whose curve is known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "continuation/Continuation.hpp"
#include "continuation/curves/EventCurveProblem.hpp"
#include "continuation/curves/EventCurveTracer.hpp"
#include "core/MonitorGradients.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

// F_i = u_i + u_i^3 / 3 - (1 - a + c_i b + e_i), i = 0 .. n-1; the monitor "min u" is the minimum
// over the n places u_i. With c = (1, -1), e = 0 (two places): its zero as a rises is u0 = 0 at
// a = 1 + b for b < 0, u1 = 0 at a = 1 - b for b > 0: the event curve a = 1 - |b|, whose minimum
// moves from place 0 to place 1 at b = 0 (a kink of the curve in (a, b)). The places' gradients
// are the default differences.
class PlacesProblem final : public Problem, public MonitorGradients {
 public:
  PlacesProblem(double a, double b, std::vector<double> c, std::vector<double> e)
      : c_(std::move(c)), e_(std::move(e)), pattern_(size(), size()) {
    params_.add("a", a, "load");
    params_.add("b", b, "asymmetry");
    for (int i = 0; i < size(); ++i) pattern_.insert(i, i) = 0.0;
    pattern_.makeCompressed();
  }
  std::string name() const override { return "places"; }
  int size() const override { return static_cast<int>(c_.size()); }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override {
    const double a = params_.value(0), b = params_.value(1);
    F.resize(size());
    for (int i = 0; i < size(); ++i)
      F[i] = u[i] + u[i] * u[i] * u[i] / 3.0 - (1.0 - a + c_[static_cast<size_t>(i)] * b + e_[static_cast<size_t>(i)]);
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    for (int i = 0; i < size(); ++i) J.coeffRef(i, i) = 1.0 + u[i] * u[i];
    return {};
  }
  Status parameter_derivative(int p, const Vector&, Vector& dF) override {
    dF = p == 0 ? Vector::Ones(size()) : Vector(-Eigen::Map<const Vector>(c_.data(), size()));
    return {};
  }
  Vector initial_guess() override { return Vector::Ones(size()); }
  std::vector<std::string> monitor_names() const override { return {"min u"}; }
  Status monitors(const Vector& u, std::vector<double>& v) override {
    v = {u.minCoeff()};
    return {};
  }
  bool has_places(int) const override { return true; }
  Status monitor_places(int, const Vector& u, std::vector<double>& v) override {
    v.assign(u.data(), u.data() + u.size());
    return {};
  }
  SolutionFields fields(const Vector&) const override { return {}; }

 private:
  std::vector<double> c_, e_;
  ParameterSet params_;
  SparseMatrix pattern_;
};

PlacesProblem two_places(double a, double b) { return PlacesProblem(a, b, {1.0, -1.0}, {0.0, 0.0}); }

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
  EventCurveTracer tracer(curve);
  ASSERT_TRUE(tracer.start(U, tight).is_ok());
  const ContinuationOptions o = in_b_to_half();
  test::RecordingObserver rec;
  const ContinuationResult r = tracer.trace(o, tight, {}, U, rec);
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
  PlacesProblem p = two_places(0.5, -0.5);
  EventCurveProblem curve(p, "a", "min u");
  Vector U = curve.state(Eigen::Vector2d(0.01, 0.5), 0.52);
  NewtonOptions tight;
  tight.residual_tolerance = 1e-12;  // two orders below what the curve is checked to
  EventCurveTracer tracer(curve);
  ASSERT_TRUE(tracer.start(U, tight).is_ok());
  EXPECT_EQ(curve.place(), 0);
  EXPECT_NEAR(U[2], 0.5, 1e-12);
  const ContinuationOptions o = in_b_to_half();
  test::RecordingObserver rec;
  const ContinuationResult r = tracer.trace(o, tight, {}, U, rec);
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

// Three places, c = (1, 1, -3), e = (0, 0.001, 0): place 1 stays level with place 0 (0.001 above
// it along the curve), and place 2, far above at b = -0.5, falls to it at b = 0: the event curve
// a = 1 + b, then a = 1 - 3 b, with the minimum moving from place 0 to place 2 at b = 0. The switch
// margin min(u1, u2) - u0 is level at about 0.001 until b = -0.00025 and falls to zero within the
// last 0.00025 before the switch: the step that crosses it (without landing on it) leaves a margin
// whose Newton linearises the level piece and whose secant creeps along it (23 corrector
// iterations). Held to place 2's piece it is smooth: corrected onto the step's row from its cubic
// interpolant's zero, then one or two Newton corrections of a chord iteration or two: at most 6.
TEST(EventCurve, APlaceOvertakingALevelOneIsLocatedOnItsOwnPiece) {
  PlacesProblem p(0.5, -0.5, {1.0, 1.0, -3.0}, {0.0, 0.001, 0.0});
  EventCurveProblem curve(p, "a", "min u");
  Vector U = curve.state(Eigen::Vector3d(0.01, 0.02, 1.5), 0.52);
  NewtonOptions tight;
  tight.residual_tolerance = 1e-12;
  EventCurveTracer tracer(curve);
  ASSERT_TRUE(tracer.start(U, tight).is_ok());
  ASSERT_EQ(curve.place(), 0);
  ContinuationOptions o = in_b_to_half();
  o.events.land_on_zeros = false;  // (a step crosses the switch)
  test::RecordingObserver rec;
  const ContinuationResult r = tracer.trace(o, tight, {}, U, rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  const int a = static_cast<int>(curve.observable_names().size()) - 3;
  std::vector<const BranchPoint*> switches;
  for (const BranchPoint& q : rec.points) {
    EXPECT_NEAR(q.observables[a], std::min(1.0 + q.lambda, 1.0 - 3.0 * q.lambda), 1e-10) << "b = " << q.lambda;
    if (q.kind == PointKind::Event && q.label == "switch") switches.push_back(&q);
  }
  ASSERT_EQ(switches.size(), 1u);
  EXPECT_NEAR(switches[0]->lambda, 0.0, 1e-10);
  EXPECT_NEAR(switches[0]->observables[a], 1.0, 1e-10);
  EXPECT_EQ(curve.place(), 2);  // not the level place 1
  EXPECT_LE(switches[0]->iterations, 6);
}

// Four places, c = (1, 1, -3, -20), e = (0, 0.001, 0, 0.0105): as above, and place 3 falls to place
// 0 at b = 0.0005, just after place 2, but is far below it at the end of the step that crosses
// both. The event curve is a = min(1 + b, 1 - 3 b, 1.0105 - 20 b): the minimum moves from place 0
// to place 2 at b = 0, then to place 3 at b = 0.0105 / 17. Held to the piece smallest at the step's
// end (place 3), the margin's zero is at b = 0.0005, where place 2 is below place 0 already: the
// first crossing lies before it, and is found on place 2's piece.
TEST(EventCurve, WhereTwoPlacesOvertakeInOneStepTheFirstIsTheSwitch) {
  PlacesProblem p(0.5, -0.5, {1.0, 1.0, -3.0, -20.0}, {0.0, 0.001, 0.0, 0.0105});
  EventCurveProblem curve(p, "a", "min u");
  Vector U = curve.state(Eigen::Vector4d(0.01, 0.02, 1.5, 2.0), 0.52);
  NewtonOptions tight;
  tight.residual_tolerance = 1e-12;
  EventCurveTracer tracer(curve);
  ASSERT_TRUE(tracer.start(U, tight).is_ok());
  ASSERT_EQ(curve.place(), 0);
  ContinuationOptions o = in_b_to_half();
  o.stop.upper = 0.05;
  o.events.land_on_zeros = false;  // (steps cross the switches)
  test::RecordingObserver rec;
  const ContinuationResult r = tracer.trace(o, tight, {}, U, rec);
  ASSERT_EQ(r.code, StopCode::UpperBound) << r.reason;
  const int a = static_cast<int>(curve.observable_names().size()) - 3, place = a + 1;
  std::vector<const BranchPoint*> switches;
  for (const BranchPoint& q : rec.points) {
    const double b = q.lambda;
    EXPECT_NEAR(q.observables[a], std::min({1.0 + b, 1.0 - 3.0 * b, 1.0105 - 20.0 * b}), 1e-10) << "b = " << b;
    if (q.kind == PointKind::Event && q.label == "switch") switches.push_back(&q);
  }
  ASSERT_EQ(switches.size(), 2u);
  EXPECT_NEAR(switches[0]->lambda, 0.0, 1e-10);
  EXPECT_EQ(switches[0]->observables[place], 0.0);  // (the row ends the piece on the place it leaves)
  EXPECT_NEAR(switches[1]->lambda, 0.0105 / 17.0, 1e-10);
  EXPECT_EQ(switches[1]->observables[place], 2.0);
  EXPECT_EQ(curve.place(), 3);
}

// The switch margin's pieces (ObservablePieces): m_j - m_k for each place j but the followed one
// k, the margin the smallest of them; which is smallest at a state, and any piece's value and
// gradient at any state, each a function of that state alone.
TEST(EventCurve, TheSwitchMarginIsTheSmallestOfItsPieces) {
  PlacesProblem p(0.5, -0.5, {1.0, 1.0, -3.0}, {0.0, 0.01, 0.0});
  EventCurveProblem curve(p, "a", "min u");
  Vector U = curve.state(Eigen::Vector3d(0.0, 0.01, 1.5), 0.5);
  ASSERT_TRUE(EventCurveTracer(curve).start(U, {}).is_ok());
  ASSERT_EQ(curve.place(), 0);
  const int margin = static_cast<int>(curve.observable_names().size()) - 1;
  const auto margin_at = [&](const Vector& X) {
    std::vector<double> v;
    EXPECT_TRUE(curve.observables(X, v).is_ok());
    return v[static_cast<size_t>(margin)];
  };
  Vector V = U;  // where place 2 is the smallest other: u2 below u1
  V[2] = 0.005;
  EXPECT_NEAR(margin_at(U), U[1] - U[0], 1e-15);  // place 1, the smallest other at U
  EXPECT_FALSE(curve.has_pieces(margin - 1));     // (the place observable has no pieces)
  ASSERT_TRUE(curve.has_pieces(margin));
  int piece = -1;
  ASSERT_TRUE(curve.smallest_piece(margin, U, piece).is_ok());
  EXPECT_EQ(piece, 1);
  ASSERT_TRUE(curve.smallest_piece(margin, V, piece).is_ok());
  EXPECT_EQ(piece, 2);
  double value = 0.0;
  ASSERT_TRUE(curve.piece_value(margin, 2, U, value).is_ok());
  EXPECT_NEAR(value, U[2] - U[0], 1e-15);  // place 2's piece, at U too
  Vector g;
  ASSERT_TRUE(curve.piece_gradient(margin, 2, U, g).is_ok());
  EXPECT_NEAR(g[2], 1.0, 1e-6);  // (the places' gradients by one-sided differences)
  EXPECT_NEAR(g[1], 0.0, 1e-6);
  EXPECT_NEAR(g[0], -1.0, 1e-6);
  // the margin and its gradient are those of the piece smallest where they are taken: no piece is
  // held by the calls before
  EXPECT_NEAR(margin_at(U), U[1] - U[0], 1e-15);
  ASSERT_TRUE(curve.observable_gradient(margin, U, g).is_ok());
  EXPECT_NEAR(g[2], 0.0, 1e-6);
  EXPECT_NEAR(g[1], 1.0, 1e-6);
  EXPECT_NEAR(g[0], -1.0, 1e-6);
  EXPECT_THROW(curve.piece_value(margin, 0, U, value), std::logic_error);  // (the followed place is no piece)
}
