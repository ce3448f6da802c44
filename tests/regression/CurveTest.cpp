// Fold curves through the real driver: `keller trace SCENE --from BRANCH.h5:ROW --curve fold
// --free PARAMETER` continues the fold stored in a branch file in a second parameter; the curve
// agrees with the folds of ordinary branches traced at its stored parameter values, is a branch
// file like any other (killed, the same command continues it), and bad starts are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "continuation/BranchFile.hpp"
#include "continuation/BranchPoint.hpp"
#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

const std::string kScene = "runs/scenes/bratu1d_shifted_fold_curve.toml";
const std::string kSmall = " --set bratu.intervals=64";

std::vector<long> rows_of_kind(const BranchTable& t, PointKind k) {
  std::vector<long> out;
  const int kind = t.column("kind");
  for (long i = 0; i < t.rows.rows(); ++i)
    if (static_cast<int>(t.rows(i, kind)) == static_cast<int>(k)) out.push_back(i);
  return out;
}

// The fold's lambda on the ordinary lambda branch of the scene at mu.
double fold_of_branch(const std::string& dir, double mu) {
  const std::string out = dir + "/mu" + std::to_string(mu) + ".h5";
  const auto r = test::run_keller("trace " + test::source_path(kScene) + kSmall +
                                  " --set bratu.mu=" + std::to_string(mu) + " -o " + out);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const BranchTable t = read_branch_table(out);
  const auto folds = rows_of_kind(t, PointKind::Fold);
  EXPECT_EQ(folds.size(), 1u) << "mu = " << mu;
  return folds.empty() ? NAN : t.rows(folds[0], t.column("lambda"));
}

}  // namespace

// The curve from the fold of the mu = 0 branch, stored at mu = 2, 4, 6, 8 (the scene's stops, now
// in mu), against the folds located to 1e-10 on lambda branches traced at those values: 1e-8.
// Killed after its sixth point, the same command continues it to the same curve.
TEST(CurveCommand, AFoldCurveFromAStoredFoldMatchesFoldsOfOrdinaryBranches) {
  const std::string dir = test::scratch_dir("curve_fold");
  const std::string scene = test::source_path(kScene);
  auto r = test::run_keller("trace " + scene + kSmall + " -o " + dir + "/branch.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable branch = read_branch_table(dir + "/branch.h5");
  const auto folds = rows_of_kind(branch, PointKind::Fold);
  ASSERT_EQ(folds.size(), 1u);
  const std::string command = "trace " + scene + kSmall + " -o " + dir + "/curve.h5 --from " + dir +
                              "/branch.h5:" + std::to_string(folds[0]) + " --curve fold --free mu";
  r = test::run_keller(command);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable curve = read_branch_table(dir + "/curve.h5");
  EXPECT_EQ(curve.parameter, "mu");
  const int mu = curve.column("mu"), lambda = curve.column("lambda");
  EXPECT_EQ(curve.rows(0, mu), 0.0);
  EXPECT_NEAR(curve.rows(0, lambda), branch.rows(folds[0], branch.column("lambda")), 1e-9);
  const auto at = rows_of_kind(curve, PointKind::Requested);
  ASSERT_EQ(at.size(), 4u);
  for (long i : at) {
    const double m = curve.rows(i, mu);
    EXPECT_NEAR(curve.rows(i, lambda), fold_of_branch(dir, m), 1e-8) << "mu = " << m;
  }
  {
    H5File f(dir + "/curve.h5", H5File::Mode::Read);
    EXPECT_EQ(f.read_string_attribute("/problem", "curve"), "fold");
  }

  // killed mid-curve: every completed point readable, the same command finishes the same curve
  const std::string killed = dir + "/killed.h5";
  std::string again = command;
  again.replace(again.find(dir + "/curve.h5"), (dir + "/curve.h5").size(), killed);
  r = test::run_keller(again, "KELLER_SIGNAL_AT=point:6 KELLER_SIGNAL=KILL");
  EXPECT_EQ(r.exit_code, -1) << r.out;
  ASSERT_TRUE(fs::exists(killed + ".part"));
  EXPECT_GE(read_branch_table(killed + ".part").rows.rows(), 6);
  r = test::run_keller(again);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("continuing the unfinished curve"), std::string::npos) << r.out;
  const BranchTable finished = read_branch_table(killed);
  const auto at2 = rows_of_kind(finished, PointKind::Requested);
  ASSERT_EQ(at2.size(), 4u);
  for (size_t k = 0; k < at.size(); ++k) {
    EXPECT_EQ(finished.rows(at2[k], mu), curve.rows(at[k], mu));
    EXPECT_NEAR(finished.rows(at2[k], lambda), curve.rows(at[k], lambda), 1e-10);
  }
  EXPECT_FALSE(fs::exists(killed + ".part"));
}

// Starts a curve cannot take get exit code 2, a message naming what is wrong, and no output.
TEST(CurveCommand, BadCurveStartsAreRefused) {
  const std::string dir = test::scratch_dir("curve_refused");
  const std::string scene = test::source_path(kScene) + kSmall;
  auto r = test::run_keller("trace " + scene + " -o " + dir + "/branch.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable branch = read_branch_table(dir + "/branch.h5");
  const auto folds = rows_of_kind(branch, PointKind::Fold);
  ASSERT_EQ(folds.size(), 1u);
  const std::string fold = dir + "/branch.h5:" + std::to_string(folds[0]);
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {" --from " + dir + "/branch.h5:0 --curve fold --free mu", "is not a located fold"},
      {" --from " + fold + " --curve fold --free lambda", "needs another free parameter"},
      {" --from " + fold + " --free mu", "go together"},
      {" --from " + fold + " --curve fold --free nu", "unknown parameter 'nu'"},
      {" --from " + fold + " --curve fold --free mu --set stability.enabled=true", "are not analysed"},
      {" --from " + fold + " --curve fold --free mu --restart " + fold, "excludes"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    r = test::run_keller("trace " + scene + " -o " + dir + "/curve.h5" + c.args);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/curve.h5"));
    EXPECT_FALSE(fs::exists(dir + "/curve.h5.part"));
  }
}
