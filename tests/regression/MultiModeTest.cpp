// Multi-mode fluids end to end (keller trace on a coarse collapsible channel, the scene's modes
// given as [fluid.modes.<name>] through --set): two Oldroyd-B modes with equal times, each with
// half the polymer viscosity, are the one-mode fluid, so their Wi branch must end at the one-mode
// branch's limiting Wi. And a mode's time is a continuation parameter: continued until it meets
// the other mode's time, the two-mode state is the one-mode state at the same Wi.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <string>

#include "continuation/engine/BranchPoint.hpp"
#include "continuation/output/BranchFile.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

const std::string kMesh =
    " --set mesh.name=custom --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set mesh.nx_downstream=5 "
    "--set mesh.ny_fluid=4 --set mesh.ny_solid=2";

std::string modes(double t1, double w1, double t2, double w2) {
  return " --set fluid.modes.slow.time=" + std::to_string(t1) +
         " --set fluid.modes.slow.viscosity=" + std::to_string(w1) +
         " --set fluid.modes.fast.time=" + std::to_string(t2) +
         " --set fluid.modes.fast.viscosity=" + std::to_string(w2);
}

BranchTable trace(const std::string& args, const std::string& out) {
  const auto r = test::run_keller("trace " + test::source_path("runs/scenes/collapsible_oldroyd_b_wi_high_gamma.toml") +
                                  kMesh + args + " -o " + out);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return read_branch_table(out);
}

}  // namespace

// Both ends are located zeros of min m1, each to the event location's tolerance (the corrector's
// 1e-10 in the residual): they agree to far better than the 1e-7 asked here.
TEST(MultiMode, TwoEqualOldroydBModesEndAtTheOneModeLimitingWi) {
  const std::string dir = test::scratch_dir("multimode_equal");
  const BranchTable one = trace("", dir + "/one.h5"), two = trace(modes(1.0, 0.5, 1.0, 0.5), dir + "/two.h5");
  const auto e1 = test::rows_of_kind(one, PointKind::End), e2 = test::rows_of_kind(two, PointKind::End);
  ASSERT_EQ(e1.size(), 1u);
  ASSERT_EQ(e2.size(), 1u);
  const double wi1 = one.rows(e1[0], one.column("Wi")), wi2 = two.rows(e2[0], two.column("Wi"));
  EXPECT_NEAR(two.rows(e2[0], two.column("min_m1")), 0.0, 1e-9);
  EXPECT_NEAR(wi2, wi1, 1e-7 * wi1);
  EXPECT_NEAR(two.rows(e2[0], two.column("max_m3")), one.rows(e1[0], one.column("max_m3")),
              1e-6 * one.rows(e1[0], one.column("max_m3")));
  std::cout << std::setprecision(12) << "limiting Wi: one mode " << wi1 << ", two equal modes " << wi2 << "\n";
}

// The fast mode's time from 0.3 to the slow mode's 1 at Wi = 0.3 (below this mesh's limiting Wi,
// 0.363) lands on the one-mode state
// there: every observable of the two branches' points at (Wi 0.3, time_fast 1) agrees to the
// Newton tolerance's effect (1e-7 relative here).
TEST(MultiMode, AModeTimeContinuedToTheOtherModesReachesTheOneModeState) {
  const std::string dir = test::scratch_dir("multimode_time");
  const std::string at_wi = " --set continuation.stops=[0.3] --set continuation.upper=0.3";
  const BranchTable one = trace(at_wi, dir + "/one.h5");
  const BranchTable two = trace(modes(1.0, 0.6, 0.3, 0.4) +
                                    " --set parameters.Wi=0.3 --set continuation.parameter=\"time_fast\" "
                                    "--set continuation.upper=1.0 --set continuation.stops=[1.0]",
                                dir + "/two.h5");
  const auto e1 = test::rows_of_kind(one, PointKind::End), e2 = test::rows_of_kind(two, PointKind::End);
  ASSERT_EQ(e1.size(), 1u);
  ASSERT_EQ(e2.size(), 1u);
  EXPECT_NEAR(one.rows(e1[0], one.column("Wi")), 0.3, 1e-12);
  EXPECT_NEAR(two.rows(e2[0], two.column("time_fast")), 1.0, 1e-12);
  int compared = 0;
  for (size_t c = 0; c < one.columns.size(); ++c) {
    const std::string& name = one.columns[c];
    if (name == "row" || name == "s" || name == "iterations" || name == "step" || name == "seconds" || name == "kind" ||
        name == "tangent_parameter" || name == "next_step" || name == "saved_slot" || name == "det_sign" ||
        name == "Wi")
      continue;
    const auto k = std::find(two.columns.begin(), two.columns.end(), name);
    if (k == two.columns.end()) continue;
    const double a = one.rows(e1[0], static_cast<long>(c)), b = two.rows(e2[0], k - two.columns.begin());
    EXPECT_NEAR(b, a, 1e-7 * std::max(1.0, std::abs(a))) << name;
    std::cout << std::setprecision(12) << name << ": one mode " << a << ", two modes " << b << "\n";
    ++compared;
  }
  EXPECT_GE(compared, 5);
}
