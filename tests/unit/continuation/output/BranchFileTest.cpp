// The branch file reads what it writes (continuation/output/BranchFile): the located points of
// /branch/events come back typed, with their kinds, parameter values and monitors by name.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "continuation/output/BranchFile.hpp"
#include "support/TestProblems.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

BranchPoint point(int index, PointKind kind, double lambda, std::string label = "") {
  BranchPoint p;
  p.index = index;
  p.kind = kind;
  p.label = std::move(label);
  p.lambda = lambda;
  p.s = 0.5 * index;
  p.u = Vector::Constant(1, lambda);
  p.tu = Vector::Zero(1);
  p.observables = {lambda};
  p.monitors = {lambda - 0.25, lambda - 0.75};
  return p;
}

}  // namespace

// Every point that is neither regular nor the start is a located point: one record each, in the
// order written, its monitor named where it is one of the file's monitors (an event, an end at a
// stop threshold) and empty otherwise (a fold's "max", an end at a bound, an event of a monitor the
// file does not list). The values are the written doubles, bit for bit.
TEST(BranchFile, ReadsTheLocatedPointsItWrote) {
  const std::string path = test::scratch_dir("branch_file_events") + "/b.h5";
  test::CubicProblem problem(0.0);
  ContinuationOptions options;
  options.parameter = "lambda";
  const std::vector<std::string> monitors = {"u - 1/2", "u < stop_below"};
  const std::vector<BranchPoint> written = {
      point(0, PointKind::Start, 0.0),
      point(1, PointKind::Regular, 0.1),
      point(2, PointKind::Event, 0.25, "u - 1/2"),
      point(3, PointKind::Fold, 0.3125, "max"),
      point(4, PointKind::Requested, 0.3),
      point(5, PointKind::BranchPoint, 1.0 / 3.0),
      point(6, PointKind::Event, 0.4, "not a monitor"),
      point(7, PointKind::Hopf, 0.45),
      point(8, PointKind::Regular, 0.5),
      point(9, PointKind::End, 0.75, "u < stop_below"),
  };
  {
    BranchFile file(path, problem, options, monitors, 1.0, {});
    for (const BranchPoint& p : written) file.on_point(p);
    file.on_finish("ended at the stop threshold", written.back());
    file.finish(0);
  }
  const BranchTable table = read_branch_table(path);
  EXPECT_EQ(table.monitors, monitors);
  struct Expected {
    int row;
    PointKind kind;
    double parameter;
    std::string monitor;
  };
  const std::vector<Expected> expected = {
      {2, PointKind::Event, 0.25, "u - 1/2"},      {3, PointKind::Fold, 0.3125, ""}, {4, PointKind::Requested, 0.3, ""},
      {5, PointKind::BranchPoint, 1.0 / 3.0, ""},  {6, PointKind::Event, 0.4, ""},   {7, PointKind::Hopf, 0.45, ""},
      {9, PointKind::End, 0.75, "u < stop_below"},
  };
  ASSERT_EQ(table.events.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    const BranchEvent& e = table.events[i];
    EXPECT_EQ(e.row, expected[i].row) << i;
    EXPECT_EQ(e.kind, expected[i].kind) << i;
    EXPECT_EQ(e.parameter, expected[i].parameter) << i;
    EXPECT_EQ(e.monitor, expected[i].monitor) << i;
  }
  EXPECT_EQ(table.located_monitor(2), "u - 1/2");
  EXPECT_EQ(table.located_monitor(9), "u < stop_below");
  EXPECT_EQ(table.located_monitor(3), "");  // a fold names no monitor
  EXPECT_EQ(table.located_monitor(1), "");  // a regular row is not located
}

// A file without located points reads as none (a branch that ended at its step budget).
TEST(BranchFile, ABranchWithoutLocatedPointsHasNoEvents) {
  const std::string path = test::scratch_dir("branch_file_no_events") + "/b.h5";
  test::CubicProblem problem(0.0);
  ContinuationOptions options;
  options.parameter = "lambda";
  {
    BranchFile file(path, problem, options, {"u - 1/2", "u < stop_below"}, 1.0, {});
    file.on_point(point(0, PointKind::Start, 0.0));
    file.on_point(point(1, PointKind::Regular, 0.1));
    file.on_finish("step budget", point(1, PointKind::Regular, 0.1));
    file.finish(std::nullopt);
  }
  const BranchTable table = read_branch_table(path);
  EXPECT_EQ(table.rows.rows(), 2);
  EXPECT_TRUE(table.events.empty());
  EXPECT_EQ(table.located_monitor(1), "");
}
