// The start modes of `keller trace --from FILE.h5:ROW --curve fold|hopf|event` (runs/CurveStarts),
// each alone: on problems whose curves are known in closed form (a fold and an event of small
// function problems, the Hopf point of the Brusselator from a branch file the test traces), what
// the run needs (the curve traced, its first state, how it begins) and the lines it says.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "continuation/output/BranchFile.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/CurveStarts.hpp"
#include "runs/ExitCode.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "support/TestProblems.hpp"
#include "support/TestSupport.hpp"
#include "support/TraceStartSupport.hpp"

using namespace keller;

namespace {

// F = u^2 - a + b: a fold in a at u = 0 where a = b, on the fold curve a = b in (b, a).
test::FunctionProblem fold_problem(double a, double b) {
  return test::FunctionProblem(
      "fold", 1, {{"a", a}, {"b", b}},
      [](const Vector& u, const Vector& p) { return Vector(Vector::Constant(1, u[0] * u[0] - p[0] + p[1])); },
      [](const Vector& u, const Vector&) { return Eigen::MatrixXd(Eigen::MatrixXd::Constant(1, 1, 2.0 * u[0])); },
      [](int k, const Vector&, const Vector&) { return Vector(Vector::Constant(1, k == 0 ? -1.0 : 1.0)); });
}

// F = u - a + b with the monitor "u": its zero in a is at a = b, the event curve a = b in (b, a).
test::FunctionProblem event_problem(double a, double b) {
  test::FunctionProblem p(
      "event", 1, {{"a", a}, {"b", b}},
      [](const Vector& u, const Vector& q) { return Vector(Vector::Constant(1, u[0] - q[0] + q[1])); },
      [](const Vector&, const Vector&) { return Eigen::MatrixXd(Eigen::MatrixXd::Ones(1, 1)); },
      [](int k, const Vector&, const Vector&) { return Vector(Vector::Constant(1, k == 0 ? -1.0 : 1.0)); });
  p.set_monitors({"u"}, [](const Vector& u) { return std::vector<double>{u[0]}; });
  return p;
}

// The located point at row 3 of a branch in a at (u, a), traced at b.
StoredPoint located(PointKind kind, double u, double a, double b, const std::string& label = "") {
  StoredPoint s;
  s.point.index = 3;
  s.point.kind = kind;
  s.point.label = label;
  s.point.lambda = a;
  s.point.u = Vector::Constant(1, u);
  s.point.tu = Vector::Ones(1);
  s.table.parameter = "a";
  s.header.parameters = {{"a", a}, {"b", b}};
  return s;
}

StoredStart from_row(const std::string& file, const std::string& row, PointKind kind) {
  StoredStart f = parse_stored_start("--from", file + ":" + row);
  f.located = kind;
  return f;
}

// An unfinished curve of this command, its last stored row the curve's state U at b.
Unfinished unfinished_curve(const Vector& U, double b) {
  Unfinished u;
  u.file = "curve.h5.part";
  u.seed.row = 4;
  u.point.index = 0;
  u.point.lambda = b;
  u.point.u = U;
  u.point.tu = Vector::Unit(U.size(), 0);
  u.state_scale = 1.5;
  u.theta = 0.75;
  return u;
}

// The real command (runs/TraceCommand), its terminal output left aside.
int run_trace_quietly(const TraceArguments& args) {
  int code = -1;
  test::said([&] { code = run_trace(args); });
  return code;
}

}  // namespace

// A fold stored off the curve (u = 1e-3, a = 0.501 at b = 0.5) is corrected onto it: u = 0 and
// a = b (Newton on the augmented system, to 1e-10); the curve begins there, in b, a new run with
// its own scales, each point's borders moved by the curve's border update.
TEST(CurveStarts, AFoldCurveBeginsAtTheStoredFoldCorrectedOntoTheCurve) {
  test::FunctionProblem problem = fold_problem(0.0, 0.0);
  TraceStart start;
  const std::string out = test::said([&] {
    start = start_fold_curve(problem, test::trace_settings_in("b"), from_row("branch.h5", "3", PointKind::Fold),
                             located(PointKind::Fold, 1e-3, 0.501, 0.5), nullptr);
  });
  ASSERT_TRUE(start.curve);
  EXPECT_EQ(&start.traced(problem), start.curve.get());
  EXPECT_EQ(start.curve->p1_name(), "a");
  EXPECT_EQ(start.begin, TraceStart::Begin::State);
  ASSERT_EQ(start.state.size(), 2);
  EXPECT_NEAR(start.state[0], 0.0, 1e-10);
  EXPECT_NEAR(start.state[1], 0.5, 1e-10);
  EXPECT_EQ(problem.parameters().get("b"), 0.5);
  EXPECT_EQ(start.options.state_scale, 0.0);
  EXPECT_FALSE(start.seed);
  EXPECT_EQ(start.event_curve, nullptr);
  EXPECT_EQ(out, "fold curve in (b, a) from the fold at row 3 of branch.h5 (a = 0.5, b = 0.5)\n");
  ASSERT_TRUE(start.borders);
  test::RecordingObserver next;
  const auto borders = start.borders(next);
  BranchPoint p;
  p.u = start.state;
  borders->on_point(p);
  EXPECT_EQ(next.points.size(), 1u);
}

// An unfinished fold curve continues from its last stored row (b = 0.6 on the curve), with its
// scales and its rows, the borders set there.
TEST(CurveStarts, AnUnfinishedFoldCurveResumesAtItsLastStoredRow) {
  test::FunctionProblem problem = fold_problem(0.0, 0.0);
  Vector U(2);
  U << 0.0, 0.6;
  const Unfinished unfinished = unfinished_curve(U, 0.6);
  TraceStart start;
  const std::string out = test::said([&] {
    start = start_fold_curve(problem, test::trace_settings_in("b"), from_row("branch.h5", "3", PointKind::Fold),
                             located(PointKind::Fold, 0.0, 0.5, 0.5), &unfinished);
  });
  EXPECT_EQ(start.begin, TraceStart::Begin::Point);
  ASSERT_TRUE(start.point);
  EXPECT_EQ(start.point->u, U);
  EXPECT_EQ(problem.parameters().get("b"), 0.6);
  EXPECT_EQ(start.options.state_scale, 1.5);
  EXPECT_EQ(start.options.theta, 0.75);
  ASSERT_TRUE(start.seed);
  EXPECT_EQ(start.seed->row, 4);
  EXPECT_NE(out.find("continuing the unfinished curve in curve.h5.part from its row 4 (b = 0.6; --fresh starts over)"),
            std::string::npos)
      << out;
}

// A stored point the curve's Newton cannot bring onto the curve in one iteration: exit 1, saying
// which first point failed, nothing written.
TEST(CurveStarts, AFoldCurveWhoseFirstPointFailsIsANumericalFailure) {
  test::FunctionProblem problem = fold_problem(0.0, 0.0);
  TraceSettings s = test::trace_settings_in("b");
  s.newton.max_iterations = 1;
  try {
    test::said([&] {
      start_fold_curve(problem, s, from_row("branch.h5", "3", PointKind::Fold), located(PointKind::Fold, 2.0, 0.5, 0.5),
                       nullptr);
    });
    ADD_FAILURE() << "no failure";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::numerical_failure);
    EXPECT_EQ(f.line().rfind("keller: the fold curve's first point failed: ", 0), 0u) << f.line();
  }
}

// The event u = 0 stored at a = 0.5 (b = 0.5) starts the event curve a = b: its first state on it,
// each piece ending at the switch margin (the scene's stop observable left aside, saying so).
TEST(CurveStarts, AnEventCurveBeginsAtTheStoredZeroOfItsMonitor) {
  test::FunctionProblem problem = event_problem(0.0, 0.0);
  TraceSettings s = test::trace_settings_in("b");
  s.continuation.stop.observable = "u";
  TraceStart start;
  const std::string out = test::said([&] {
    start = start_event_curve(problem, s, from_row("branch.h5", "3", PointKind::Event),
                              located(PointKind::Event, 0.0, 0.5, 0.5, "u"), nullptr);
  });
  EXPECT_EQ(start.begin, TraceStart::Begin::EventCurve);
  ASSERT_TRUE(start.curve);
  EXPECT_EQ(start.event_curve, start.curve.get());
  EXPECT_NE(start.event_tracer, nullptr);
  ASSERT_EQ(start.state.size(), 2);
  EXPECT_NEAR(start.state[0], 0.0, 1e-12);
  EXPECT_NEAR(start.state[1], 0.5, 1e-12);
  EXPECT_EQ(start.options.stop.observable, EventCurveProblem::kMargin);
  EXPECT_EQ(start.options.stop.below, 0.0);
  EXPECT_EQ(start.options.stop.above, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(start.borders);
  EXPECT_EQ(out,
            "note: continuation.stop_observable (u) is left aside: an event curve's pieces end where the minimum's "
            "place moves\n"
            "event curve of u = 0 in (b, a) from row 3 of branch.h5 (a = 0.5, b = 0.5), the minimum at place 0\n");
}

// An unfinished event curve begins at its last stored row's state, at its value of b.
TEST(CurveStarts, AnUnfinishedEventCurveBeginsAtItsLastStoredRow) {
  test::FunctionProblem problem = event_problem(0.0, 0.0);
  Vector U(2);
  U << 0.0, 0.7;
  const Unfinished unfinished = unfinished_curve(U, 0.7);
  TraceStart start;
  test::said([&] {
    start = start_event_curve(problem, test::trace_settings_in("b"), from_row("branch.h5", "3", PointKind::Event),
                              located(PointKind::Event, 0.0, 0.5, 0.5, "u"), &unfinished);
  });
  EXPECT_EQ(start.begin, TraceStart::Begin::EventCurve);
  ASSERT_EQ(start.state.size(), 2);
  EXPECT_NEAR(start.state[1], 0.7, 1e-12);
  EXPECT_EQ(problem.parameters().get("b"), 0.7);
  EXPECT_EQ(start.options.state_scale, 1.5);
  ASSERT_TRUE(start.seed);
  EXPECT_EQ(start.seed->row, 4);
}

// A row that is no zero of a monitor of the problem is bad input naming its monitors.
TEST(CurveStarts, AnEventCurveFromTheZeroOfNoMonitorIsRefused) {
  test::FunctionProblem problem = event_problem(0.0, 0.0);
  try {
    start_event_curve(problem, test::trace_settings_in("b"), from_row("branch.h5", "3", PointKind::Event),
                      located(PointKind::Event, 0.0, 0.5, 0.5, "v"), nullptr);
    ADD_FAILURE() << "not refused";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::usage);
    EXPECT_EQ(f.reason(),
              "--from 'branch.h5': row 3 (v) is not the zero of a monitor of this problem (its monitors: u)");
  }
}

// The Hopf point of the Brusselator's b branch at a = 2 (b = 1 + a^2 = 5, omega = a = 2, exact on
// the grid), from the branch file traced with its stability: the curve begins on it (to 1e-8,
// Newton's tolerance); a row of a branch traced without [stability] has no eigenvector to start
// from, which is bad input.
TEST(CurveStarts, AHopfCurveBeginsAtTheStoredHopfPointFromItsEigenvector) {
  const std::string dir = test::scratch_dir("curve_starts_hopf");
  const std::string scene = test::source_path("runs/scenes/brusselator1d_hopf.toml");
  const std::vector<std::string> overrides = {"brusselator.intervals=8"};
  TraceArguments trace;
  trace.scene = scene;
  trace.output = dir + "/branch.h5";
  trace.overrides = overrides;
  ASSERT_EQ(run_trace_quietly(trace), 0);
  trace.output = dir + "/plain.h5";
  trace.overrides.push_back("stability.enabled=false");
  ASSERT_EQ(run_trace_quietly(trace), 0);

  const LoadedScene loaded = load_scene(scene, declare_trace_keys, overrides);
  auto problem = loaded.type->build(loaded.scene);
  const TraceSettings settings = TraceSettings::from_scene(loaded.scene, "a");
  const StoredStart from = from_row(dir + "/branch.h5", "hopf1", PointKind::Hopf);
  std::vector<std::string> warnings;
  const StoredPoint hopf = read_stored_start(from, loaded, *problem, "a", warnings);
  TraceStart start;
  const std::string out = test::said([&] { start = start_hopf_curve(*problem, settings, from, hopf, nullptr); });
  ASSERT_TRUE(start.curve);
  EXPECT_EQ(start.begin, TraceStart::Begin::State);
  const long n = problem->size();
  ASSERT_EQ(start.state.size(), n + 2);
  EXPECT_NEAR(start.state[n], 5.0, 1e-8);      // b
  EXPECT_NEAR(start.state[n + 1], 2.0, 1e-8);  // omega
  EXPECT_EQ(problem->parameters().get("a"), 2.0);
  EXPECT_TRUE(start.borders);
  EXPECT_EQ(out.rfind("Hopf curve in (a, b) from the Hopf point at row " + std::to_string(hopf.point.index), 0), 0u)
      << out;

  const StoredStart plain = from_row(dir + "/plain.h5", "0", PointKind::Hopf);
  StoredPoint row0 = hopf;
  row0.point = read_branch_point(plain.file, 0);
  try {
    start_hopf_curve(*problem, settings, plain, row0, nullptr);
    ADD_FAILURE() << "not refused";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::usage);
    EXPECT_NE(f.reason().find("row 0 has no stored critical eigenvector"), std::string::npos) << f.reason();
  }
}
