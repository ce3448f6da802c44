// How `keller trace` begins (runs/TraceStart): its settings from the scene, what it reads before
// anything is computed (read_trace_source: the stored point, the unfinished run an earlier run of
// the same command left), and which start mode trace_start picks for each command line, with the
// state scale of a new run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "runs/CommandFailure.hpp"
#include "runs/CommandRun.hpp"
#include "runs/TraceCommand.hpp"
#include "runs/TraceStart.hpp"
#include "support/TestProblems.hpp"
#include "support/TestSupport.hpp"
#include "support/TraceStartSupport.hpp"

using namespace keller;

namespace {

// F = (u0 - a, u1 - b), its state the parameter values; the monitor u0.
test::FunctionProblem identity(double a, double b) {
  test::FunctionProblem p(
      "identity", 2, {{"a", a}, {"b", b}}, [](const Vector& u, const Vector& q) { return Vector(u - q); },
      [](const Vector&, const Vector&) { return Eigen::MatrixXd(Eigen::MatrixXd::Identity(2, 2)); },
      [](int k, const Vector&, const Vector&) { return Vector(-Vector::Unit(2, k)); });
  p.set_monitors({"u0"}, [](const Vector& u) { return std::vector<double>{u[0]}; });
  return p;
}

// Row 3 of a branch in `parameter` at `lambda`, its state u, traced at a = 0 and b = 0.
TraceSource stored_at(const std::string& parameter, double lambda, const Vector& u,
                      PointKind kind = PointKind::Requested) {
  TraceSource source;
  StoredPoint& s = source.stored.emplace();
  s.point.index = 3;
  s.point.kind = kind;
  s.point.label = "u0";
  s.point.lambda = lambda;
  s.point.u = u;
  s.point.tu = Vector::Unit(u.size(), 0);
  s.table.parameter = parameter;
  s.table.state_scale = 2.5;
  s.header.parameters = {{"a", 0.0}, {"b", 0.0}};
  return source;
}

std::optional<StoredStart> flag(const std::string& name, PointKind located = PointKind::Fold) {
  StoredStart f = parse_stored_start(name, "branch.h5:3");
  f.located = located;
  return f;
}

const Scene& no_scene() {
  static const LoadedScene loaded =
      load_scene_text("[problem]\ntype = \"bratu1d\"\n", "test scene", declare_trace_keys);
  return loaded.scene;
}

// trace_start with the standard output captured.
TraceStart start_quietly(Problem& problem, const TraceSettings& s, const std::optional<StoredStart>& from,
                         const TraceSource& source, int direction = 1) {
  TraceStart start;
  test::said([&] { start = trace_start(problem, s, from, source, no_scene(), direction); });
  return start;
}

}  // namespace

// The scene's options, the continuation's parameter --free's where given.
TEST(TraceStart, SettingsAreTheScenesWithTheFreeParameter) {
  const LoadedScene loaded = load_scene_text(
      "[problem]\ntype = \"bratu1d\"\n[continuation]\nparameter = \"lambda\"\ninitial_step = 0.25\n"
      "[newton]\nmax_iterations = 7\n[start]\nhomotopy = \"off\"\n",
      "test scene", declare_trace_keys);
  const TraceSettings s = TraceSettings::from_scene(loaded.scene);
  EXPECT_EQ(s.continuation.parameter, "lambda");
  EXPECT_EQ(s.continuation.step.initial, 0.25);
  EXPECT_EQ(s.newton.max_iterations, 7);
  EXPECT_EQ(s.start.path, StartOptions::Path::Off);
  EXPECT_FALSE(s.stability.enabled);
  EXPECT_EQ(TraceSettings::from_scene(loaded.scene, "mu").continuation.parameter, "mu");
}

// No start on the command line: a fresh branch from the solved state (a, b) = (3, 4), whose state
// scale is its RMS, sqrt(12.5).
TEST(TraceStart, WithoutAStartTheBranchIsFreshWithTheRmsOfItsStateAsScale) {
  test::FunctionProblem problem = identity(3.0, 4.0);
  const TraceStart start = start_quietly(problem, test::trace_settings_in("a"), std::nullopt, {});
  EXPECT_EQ(start.begin, TraceStart::Begin::State);
  EXPECT_NEAR(start.state[0], 3.0, 1e-14);
  EXPECT_NEAR(start.state[1], 4.0, 1e-14);
  EXPECT_NEAR(start.options.state_scale, std::sqrt(12.5), 1e-14);
}

// An unfinished run is continued, with --restart as without; its scale is its own (1 where its
// file has none: a resumed run has no first state to measure).
TEST(TraceStart, AnUnfinishedRunIsContinuedWithItsScale) {
  test::FunctionProblem problem = identity(0.0, 0.0);
  TraceSource source = stored_at("a", 1.0, Vector::Ones(2));
  Unfinished& u = source.unfinished.emplace();
  u.seed.row = 7;
  u.point.lambda = 0.5;
  u.point.u = Vector::Constant(2, 0.5);
  u.state_scale = 0.75;
  for (const auto& from : {std::optional<StoredStart>(), flag("--restart")}) {
    const TraceStart start = start_quietly(problem, test::trace_settings_in("a"), from, source);
    EXPECT_EQ(start.begin, TraceStart::Begin::Point);
    ASSERT_TRUE(start.seed);
    EXPECT_EQ(start.seed->row, 7);
    EXPECT_EQ(start.options.state_scale, 0.75);
  }
  source.unfinished->state_scale = 0.0;
  EXPECT_EQ(start_quietly(problem, test::trace_settings_in("a"), std::nullopt, source).options.state_scale, 1.0);
}

// --restart in the stored branch's parameter resumes at the point, in another parameter starts a
// new branch from its state (scale: its RMS, 1); --switch switches to the side asked for.
TEST(TraceStart, AStoredPointIsRestartedFromOrSwitchedAt) {
  test::FunctionProblem problem = identity(0.0, 0.0);
  const TraceSource in_a = stored_at("a", 1.0, Vector::Ones(2));
  TraceStart start = start_quietly(problem, test::trace_settings_in("a"), flag("--restart"), in_a);
  EXPECT_EQ(start.begin, TraceStart::Begin::Point);
  EXPECT_EQ(start.options.state_scale, 2.5);
  start = start_quietly(problem, test::trace_settings_in("b"), flag("--restart"), in_a);
  EXPECT_EQ(start.begin, TraceStart::Begin::State);
  EXPECT_EQ(start.state, Vector::Ones(2));
  EXPECT_EQ(start.options.state_scale, 1.0);
  start = start_quietly(problem, test::trace_settings_in("a"), flag("--switch"), in_a, -1);
  EXPECT_EQ(start.begin, TraceStart::Begin::Switch);
  EXPECT_EQ(start.direction, -1);
}

// --from with --curve event starts the event curve of the stored zero of u0 (at a = 0) in b.
TEST(TraceStart, ACurveFromAStoredPointIsTheCurveOfItsKind) {
  test::FunctionProblem problem = identity(0.0, 0.0);
  Vector u(2);
  u << 0.0, 0.0;
  const TraceStart start = start_quietly(problem, test::trace_settings_in("b"), flag("--from", PointKind::Event),
                                         stored_at("a", 0.0, u, PointKind::Event));
  EXPECT_EQ(start.begin, TraceStart::Begin::EventCurve);
  ASSERT_TRUE(start.curve);
  EXPECT_EQ(start.curve->p1_name(), "a");
}

// What the run starts from, read from files the real command wrote: the stored point of
// --restart (nothing left by an earlier run); the unfinished run a run stopped by an error left in
// OUT.h5.part (its last stored row and scales), which --fresh discards and which another run
// (another start) may not take over.
TEST(TraceStart, ReadsTheStoredPointAndTheUnfinishedRunOfThisCommand) {
  const std::string dir = test::scratch_dir("trace_start_source");
  TraceArguments args;
  args.scene = test::source_path("runs/scenes/bratu1d_fold.toml");
  args.overrides = {"bratu.intervals=16"};
  args.output = dir + "/branch.h5";
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  const int traced = run_trace(args);
  args.output = dir + "/out.h5";
  ::setenv("KELLER_SIGNAL_AT", "point:5", 1);
  ::setenv("KELLER_SIGNAL", "THROW", 1);
  const int stopped = run_trace(args);  // an internal error after the fifth point
  ::unsetenv("KELLER_SIGNAL_AT");
  ::unsetenv("KELLER_SIGNAL");
  testing::internal::GetCapturedStderr();
  testing::internal::GetCapturedStdout();
  ASSERT_EQ(traced, 0);
  ASSERT_EQ(stopped, 4);

  RunSummary summary;
  CommandRun run(summary, {"branch", "branch file", "rows", "point", "/branch/exit_code", "", ""});
  run.load(args.scene, args.output, declare_trace_keys, args.overrides);
  Problem& problem = run.build();
  const std::string record = trace_run_record(run.loaded(), args);
  testing::internal::CaptureStdout();
  const TraceSource source = read_trace_source(
      run, record, false, parse_stored_start("--restart", dir + "/branch.h5:fold1"), problem, "lambda");
  testing::internal::GetCapturedStdout();
  EXPECT_EQ(source.left.kind, LeftRun::Kind::unfinished);
  ASSERT_TRUE(source.unfinished);
  EXPECT_EQ(source.unfinished->file, dir + "/out.h5.part");
  EXPECT_GE(source.unfinished->seed.row, 3);
  EXPECT_EQ(source.unfinished->point.index, source.unfinished->seed.row);
  EXPECT_EQ(source.unfinished->state_scale, read_branch_table(dir + "/out.h5.part").state_scale);
  EXPECT_FALSE(source.stored);  // an unfinished branch continues from its own rows

  testing::internal::CaptureStdout();
  const TraceSource fresh = read_trace_source(
      run, record, true, parse_stored_start("--restart", dir + "/branch.h5:fold1"), problem, "lambda");
  const std::string note = testing::internal::GetCapturedStdout();
  EXPECT_EQ(fresh.left.kind, LeftRun::Kind::none);
  EXPECT_FALSE(fresh.unfinished);
  ASSERT_TRUE(fresh.stored);
  EXPECT_EQ(fresh.stored->point.kind, PointKind::Fold);
  EXPECT_TRUE(fresh.warnings.empty());
  EXPECT_NE(note.find("--fresh"), std::string::npos) << note;

  TraceArguments other = args;
  other.restart = dir + "/branch.h5:fold1";
  EXPECT_THROW(read_trace_source(run, trace_run_record(run.loaded(), other), false, std::nullopt, problem, "lambda"),
               std::invalid_argument);
}
