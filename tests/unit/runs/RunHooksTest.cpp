// runs/RunHooks: what a program that embeds keller's commands (the Python package) sees of a run,
// on synthetic points: nothing without a hook, the names and values of a branch point and of a time
// step, and a hook's false as a stop request (InterruptGuard), as Ctrl-C makes one.
#include <gtest/gtest.h>

#include "problems/analytic/Bratu1DProblem.hpp"
#include "runs/Interrupts.hpp"
#include "runs/RunHooks.hpp"

namespace keller {
namespace {

TEST(RunHooks, NoHookNoObserver) {
  EXPECT_EQ(branch_hook("lambda"), nullptr);
  Bratu1DProblem problem(8, 1.0);
  EXPECT_EQ(time_hook(problem), nullptr);
}

TEST(RunHooks, ABranchPointReachesTheHookWithItsNamesAndValues) {
  std::vector<RunPoint> seen;
  const RunHookScope scope([&](const RunPoint& p) {
    seen.push_back(p);
    return true;
  });
  const auto observer = branch_hook("lambda");
  ASSERT_NE(observer, nullptr);
  observer->on_start({"u_max"}, {"m"});
  BranchPoint p;
  p.index = 7;
  p.kind = PointKind::Fold;
  p.label = "max";
  p.lambda = 3.5;
  p.u = Vector::Constant(4, 2.0);
  p.observables = {1.25};
  p.monitors = {-0.5, 0.75};  // the problem's monitor, then a stop threshold's
  observer->on_point(p);
  ASSERT_EQ(seen.size(), 1u);
  const RunPoint& r = seen[0];
  EXPECT_EQ(r.command, "trace");
  EXPECT_EQ(r.row, 7);
  EXPECT_EQ(r.kind, "fold");
  EXPECT_EQ(r.label, "max");
  EXPECT_EQ(r.names, (std::vector<std::string>{"lambda", "u_max", "m"}));  // the threshold has no name here
  EXPECT_EQ(r.values, (std::vector<double>{3.5, 1.25, -0.5}));
  ASSERT_NE(r.u, nullptr);
  EXPECT_EQ(r.u->size(), 4);
}

TEST(RunHooks, AStepReachesTheHookWithTimeAndObservables) {
  std::vector<RunPoint> seen;
  const RunHookScope scope([&](const RunPoint& p) {
    seen.push_back(p);
    return true;
  });
  Bratu1DProblem problem(8, 1.0);
  const auto observer = time_hook(problem);
  TimePoint t;
  t.step = 3;
  t.t = 0.25;
  t.u = Vector::Zero(problem.size());
  observer->on_step(t);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].kind, "step");
  EXPECT_EQ(seen[0].row, 3);
  EXPECT_EQ(seen[0].names.front(), "t");
  EXPECT_EQ(seen[0].values.front(), 0.25);
  EXPECT_EQ(seen[0].names.size(), 1 + problem.observable_names().size());
}

TEST(RunHooks, AHookThatReturnsFalseRequestsAStopAsASignalDoes) {
  const InterruptGuard guard;
  EXPECT_FALSE(InterruptGuard::requested());
  int calls = 0;
  const RunHookScope scope([&](const RunPoint&) { return ++calls < 2; });
  const auto observer = branch_hook("lambda");
  observer->on_start({}, {});
  BranchPoint p;
  p.u = Vector::Zero(2);
  observer->on_point(p);
  EXPECT_FALSE(InterruptGuard::requested());
  observer->on_point(p);
  EXPECT_TRUE(InterruptGuard::requested());
}

}  // namespace
}  // namespace keller
