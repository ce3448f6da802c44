// The start modes of `keller trace` for a branch of the scene's own problem (runs/BranchStarts),
// each alone on small problems with known answers: what the run needs (how it begins, from where,
// with which options and parameter values) and the line it says.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "runs/BranchStarts.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/ExitCode.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "support/TestProblems.hpp"
#include "support/TraceStartSupport.hpp"

using namespace keller;

namespace {

// F = (u0 - a, u1 - b): the state is the parameter values.
test::FunctionProblem identity(double a, double b) {
  return test::FunctionProblem(
      "identity", 2, {{"a", a}, {"b", b}}, [](const Vector& u, const Vector& p) { return Vector(u - p); },
      [](const Vector&, const Vector&) { return Eigen::MatrixXd(Eigen::MatrixXd::Identity(2, 2)); },
      [](int k, const Vector&, const Vector&) { return Vector(-Vector::Unit(2, k)); });
}

// A stored point of a branch in `parameter` at `lambda`, its branch traced at `others`.
StoredPoint stored_point(const std::string& parameter, double lambda, const Vector& u,
                         const std::map<std::string, double>& others) {
  StoredPoint s;
  s.point.index = 3;
  s.point.lambda = lambda;
  s.point.u = u;
  s.point.tu = Vector::Unit(u.size(), 0);
  s.table.parameter = parameter;
  s.table.state_scale = 2.5;
  s.table.theta = 0.25;
  s.header.parameters = others;
  return s;
}

StoredStart stored_start(const std::string& flag) { return parse_stored_start(flag, "branch.h5:3"); }

}  // namespace

// Fresh: Newton from the cubic's guess u = -2 at lambda = 0 reaches the root -sqrt(3) (to 1e-10 / 6:
// Newton's tolerance on |F| = |u^3 - 3u|, whose slope there is 6); the run begins at that state,
// with the factorisation of J made there, and the scene's options (no state scale yet: its own).
TEST(BranchStarts, AFreshBranchBeginsAtTheSolvedFirstState) {
  test::CubicProblem problem(0.0);
  TraceStart start;
  const std::string out = test::said([&] { start = start_fresh(problem, test::trace_settings_in("lambda")); });
  EXPECT_EQ(start.begin, TraceStart::Begin::State);
  ASSERT_EQ(start.state.size(), 1);
  EXPECT_NEAR(start.state[0], -std::sqrt(3.0), 1e-10 / 6.0);
  EXPECT_TRUE(start.factorisation.lu);
  EXPECT_FALSE(start.point);
  EXPECT_FALSE(start.curve);
  EXPECT_FALSE(start.seed);
  EXPECT_EQ(start.options.state_scale, 0.0);
  EXPECT_NE(out.find("first steady state at lambda = 0\n"), std::string::npos) << out;
  EXPECT_NE(out.find("first steady state: "), std::string::npos) << out;
}

// Fresh, where there is no state: u^2 + 1 = 0 has no real root, and without a path from an
// easier state the first steady state fails: exit 1, saying so.
TEST(BranchStarts, AFreshBranchWithoutASteadyStateIsANumericalFailure) {
  test::FunctionProblem problem(
      "no-root", 1, {{"lambda", 0.0}}, [](const Vector& u, const Vector&) { return Vector(u.array().square() + 1.0); },
      [](const Vector& u, const Vector&) { return Eigen::MatrixXd(Eigen::MatrixXd::Constant(1, 1, 2.0 * u[0])); },
      [](int, const Vector&, const Vector&) { return Vector(Vector::Zero(1)); });
  TraceSettings s = test::trace_settings_in("lambda");
  s.start.path = StartOptions::Path::Off;
  s.newton.max_iterations = 5;
  try {
    test::said([&] { start_fresh(problem, s); });
    ADD_FAILURE() << "no failure";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::numerical_failure);
    EXPECT_EQ(f.line().rfind("keller: the first steady state failed: ", 0), 0u) << f.line();
    EXPECT_NE(f.line().find("; no output written"), std::string::npos) << f.line();
  }
}

// Unfinished: the run resumes at the file's last stored row, with the scales its branch was traced
// with, numbered after the rows the file keeps (its seed), at that row's parameter value.
TEST(BranchStarts, AnUnfinishedBranchResumesAtItsLastStoredRow) {
  test::FunctionProblem problem = identity(0.0, 0.0);
  Unfinished u;
  u.file = "out.h5.part";
  u.seed.row = 5;
  u.point = stored_point("a", 0.7, Vector::Constant(2, 0.7), {}).point;
  u.state_scale = 3.5;
  u.theta = 0.125;
  TraceStart start;
  const std::string out = test::said([&] { start = continue_unfinished(problem, test::trace_settings_in("a"), u); });
  EXPECT_EQ(start.begin, TraceStart::Begin::Point);
  ASSERT_TRUE(start.point);
  EXPECT_EQ(start.point->lambda, 0.7);
  ASSERT_TRUE(start.seed);
  EXPECT_EQ(start.seed->row, 5);
  EXPECT_EQ(start.options.state_scale, 3.5);
  EXPECT_EQ(start.options.theta, 0.125);
  EXPECT_EQ(problem.parameters().get("a"), 0.7);
  EXPECT_EQ(out, "continuing the unfinished branch in out.h5.part from its row 5 (a = 0.7; --fresh starts over)\n");
}

// Restart: from the stored point with its tangent and its branch's scales, at its parameter value.
TEST(BranchStarts, ARestartResumesAtTheStoredPointWithItsBranchsScales) {
  test::FunctionProblem problem = identity(0.0, 0.25);
  const StoredPoint stored = stored_point("a", 1.5, Vector::Constant(2, 1.5), {{"b", 0.25}});
  TraceStart start;
  const std::string out = test::said(
      [&] { start = start_at_point(problem, test::trace_settings_in("a"), stored_start("--restart"), stored, -1); });
  EXPECT_EQ(start.begin, TraceStart::Begin::Point);
  ASSERT_TRUE(start.point);
  EXPECT_EQ(start.point->u, stored.point.u);
  EXPECT_EQ(start.options.state_scale, 2.5);
  EXPECT_EQ(start.options.theta, 0.25);
  EXPECT_EQ(problem.parameters().get("a"), 1.5);
  EXPECT_FALSE(start.seed);
  EXPECT_EQ(out, "restarting from row 3 of branch.h5 (a = 1.5)\n");
}

// Switch: the same point, begun by a switch to the side --switch-direction names.
TEST(BranchStarts, ASwitchBeginsAtTheStoredBranchPointOnTheGivenSide) {
  test::FunctionProblem problem = identity(0.0, 0.25);
  const StoredPoint stored = stored_point("a", 1.5, Vector::Constant(2, 1.5), {{"b", 0.25}});
  TraceStart start;
  const std::string out = test::said(
      [&] { start = start_at_point(problem, test::trace_settings_in("a"), stored_start("--switch"), stored, -1); });
  EXPECT_EQ(start.begin, TraceStart::Begin::Switch);
  EXPECT_EQ(start.direction, -1);
  EXPECT_EQ(start.options.state_scale, 2.5);
  EXPECT_EQ(out, "switching branches at row 3 of branch.h5 (a = 1.5)\n");
}

// Another parameter: a new branch in b from the state of a point of a branch in a, at every value
// of the point (a its own, b its branch's), with a tangent and scales of its own; where the scene
// sets b elsewhere, a note says which value the branch starts at.
TEST(BranchStarts, ABranchInAnotherParameterBeginsAtTheStoredStateAndItsValues) {
  const LoadedScene loaded = load_scene_text(
      "[problem]\ntype = \"brusselator1d\"\n[brusselator]\nintervals = 4\n[parameters]\na = 2.0\nb = 3.0\n"
      "[continuation]\nparameter = \"a\"\n",
      "test scene", declare_trace_keys);
  auto problem = loaded.type->build(loaded.scene);
  const Vector u = Vector::LinSpaced(problem->size(), 1.0, 2.0);
  const StoredPoint stored = stored_point("b", 4.0, u, {{"a", 2.5}, {"D_u", 1.0}, {"D_v", 1.0}});
  TraceStart start;
  const std::string out = test::said([&] {
    start = start_in_other_parameter(*problem, test::trace_settings_in("a"), stored_start("--restart"), stored,
                                     loaded.scene);
  });
  EXPECT_EQ(start.begin, TraceStart::Begin::State);
  EXPECT_EQ(start.state, u);
  EXPECT_FALSE(start.point);
  EXPECT_EQ(start.options.state_scale, 0.0);
  EXPECT_EQ(start.options.theta, 0.5);
  EXPECT_EQ(problem->parameters().get("a"), 2.5);
  EXPECT_EQ(problem->parameters().get("b"), 4.0);
  EXPECT_EQ(out,
            "starting a branch in a at row 3 of branch.h5, a branch in b (b = 4, a = 2.5)\n"
            "note: a starts at the stored point's value 2.5, not at the scene's 2\n");
}
