// Hard cases of the collapsible channel stay numerically stable (CTest label "hard"; coarse
// meshes, through the real driver): each branch ends with a located event or a recorded reason,
// never a crash, a NaN in the branch table, or an inverted element (fluid mesh or solid) passed
// off as a solution.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "continuation/BranchFile.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

const char* kCoarse =
    " --set mesh.name=custom --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set mesh.nx_downstream=5"
    " --set mesh.ny_fluid=4 --set mesh.ny_solid=2";

BranchTable trace(const std::string& name, const std::string& scene, const std::string& overrides) {
  const std::string dir = test::scratch_dir("hard_" + name);
  const std::string out = dir + "/" + name + ".h5";
  const test::CommandResult r =
      test::run_keller("trace " + test::source_path("runs/scenes/" + scene) + " -o " + out + kCoarse + " " + overrides);
  std::printf("%s", r.out.substr(r.out.size() > 600 ? r.out.size() - 600 : 0).c_str());
  // 0: ended at a bound, an event or a stop; 1: ended at the step-size floor with its reason
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;
  const BranchTable t = read_branch_table(out);
  EXPECT_FALSE(t.status.empty());
  EXPECT_EQ(t.status.find("running"), std::string::npos) << t.status;
  for (int i = 0; i < t.rows.rows(); ++i)
    for (int j = 0; j < t.rows.cols(); ++j) EXPECT_TRUE(std::isfinite(t.rows(i, j))) << t.columns[j] << " row " << i;
  for (int i = 0; i < t.rows.rows(); ++i) {
    EXPECT_GT(t.rows(i, t.column("mesh_quality")), 0.0) << "row " << i;
    EXPECT_GT(t.rows(i, t.column("min_detF")), 0.0) << "row " << i;
  }
  return t;
}

double last(const BranchTable& t, const std::string& col) { return t.rows(t.rows.rows() - 1, t.column(col)); }

}  // namespace

TEST(HardCases, OldroydBUpToItsLimitingWi) {
  const BranchTable t = trace("oldroyd_b", "collapsible_oldroyd_b_wi_low_gamma.toml", "");
  // the branch stops at the located zero of min m1 (kind 3 = event, then the end row)
  EXPECT_NE(t.status.find("min_m1"), std::string::npos) << t.status;
  // located to event_tolerance = 1e-8 in Wi, where min m1 falls by O(10) per unit Wi
  EXPECT_NEAR(last(t, "min_m1"), 0.0, 1e-6);
  EXPECT_GT(last(t, "Wi"), 0.01);
}

TEST(HardCases, FenePNearItsExtensibilityLimit) {
  // b = 5: tr M < 3b = 15 must hold at every node of every point; traced past the loss of
  // positive definiteness (located as an event) up to Wi = 8
  const BranchTable t = trace("fene_p", "collapsible_fene_p_wi_high_gamma.toml",
                              "--set parameters.b=5 --set continuation.stop_below=-1e300");
  // (the kernels refuse states with tr M >= 3b at any conformation node: the branch then ends at
  // the step floor with that reason instead of passing such a state off as a solution)
  for (int i = 0; i < t.rows.rows(); ++i) EXPECT_LT(t.rows(i, t.column("max_trM")), 15.0) << "row " << i;
  const bool at_bound = t.status.find("upper bound") != std::string::npos;
  const bool at_limit = t.status.find("3b") != std::string::npos;
  EXPECT_TRUE(at_bound || at_limit) << t.status;
  EXPECT_GT(last(t, "max_trM"), 14.0);  // at the spring's limit
}

TEST(HardCases, OwensAtWi5) {
  const BranchTable t = trace("owens", "collapsible_owens_wi_high_gamma.toml",
                              "--set continuation.upper=5 --set continuation.stop_below=-1e300");
  EXPECT_NE(t.status.find("upper bound"), std::string::npos) << t.status;
  EXPECT_DOUBLE_EQ(last(t, "Wi"), 5.0);
}

TEST(HardCases, ThinnestWallAtTheLargestGamma) {
  const BranchTable t = trace("thin", "collapsible_newtonian_thickness.toml", "--set parameters.Gamma=6.6e-4");
  EXPECT_DOUBLE_EQ(last(t, "t"), 0.1);
  EXPECT_GT(last(t, "dy_max"), 1.0);  // the thin wall bulges out by more than the channel width
}

TEST(HardCases, StrongestCollapseAtTheSmallestGamma) {
  const BranchTable t = trace("collapse", "collapsible_newtonian_thickness.toml", "--set parameters.Gamma=4.95e-5");
  EXPECT_DOUBLE_EQ(last(t, "t"), 0.1);
  EXPECT_GT(last(t, "gap_min"), 0.0);
  EXPECT_LT(last(t, "gap_min"), 0.4);
}
