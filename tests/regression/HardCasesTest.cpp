// Hard cases of the collapsible channel stay numerically stable (CTest label "hard"; coarse
// meshes, through the real driver): each branch of tests/regression/hard_cases.txt ends with a
// located event or a recorded reason, never a crash, a NaN in the branch table, or an inverted
// element (fluid mesh or solid) passed off as a solution; its located points are those of its
// checked-in reference (what the hard-case table of docs/collapsible.md reports); and what makes each case
// hard holds (tr M < 3b, min m1 > 0 in the log form, ...). Also: a first steady state that
// fails writes nothing and says why, and a restart from the last point of a branch that ended at
// the step floor ends again with its reason instead of failing in another way.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "continuation/output/BranchFile.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

// An end at the step-size floor lies where the step controller gave up, which depends on the
// path the branch took: it is not compared with the reference (tests/tools/regenerate_references.py)
const char* step_floor = "fell below min_step";

struct HardCase {
  std::string scene, overrides;
};

std::map<std::string, HardCase> hard_cases() {
  std::ifstream in(test::source_path("tests/regression/hard_cases.txt"));
  std::map<std::string, HardCase> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> parts;
    std::stringstream ss(line);
    for (std::string p; std::getline(ss, p, '|');) parts.push_back(p);
    auto trim = [](std::string s) {
      s.erase(0, s.find_first_not_of(' '));
      s.erase(s.find_last_not_of(' ') + 1);
      return s;
    };
    std::string overrides;
    std::stringstream ov(parts.size() > 2 ? parts[2] : "");
    for (std::string o; ov >> o;) overrides += " --set " + o;
    out[trim(parts[0])] = {trim(parts[1]), overrides};
  }
  return out;
}

std::pair<std::vector<std::string>, std::vector<std::vector<double>>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line, c;
  std::vector<std::string> cols;
  std::vector<std::vector<double>> rows;
  std::getline(in, line);
  std::stringstream h(line);
  while (std::getline(h, c, ',')) cols.push_back(c);
  while (std::getline(in, line)) {
    std::stringstream r(line);
    std::vector<double> row;
    while (std::getline(r, c, ',')) row.push_back(std::stod(c));
    rows.push_back(row);
  }
  return {cols, rows};
}

// Traces a hard case, checks what every hard case must satisfy and, without `extra` overrides,
// its located points against its reference; returns its branch. `file` receives its path.
BranchTable trace(const std::string& name, const std::string& extra = "", std::string* file = nullptr) {
  const HardCase c = hard_cases().at(name);
  const std::string dir = test::scratch_dir("hard_" + name + (extra.empty() ? "" : "_extra"));
  const std::string out = dir + "/" + name + ".h5";
  if (file) *file = out;
  const test::CommandResult r = test::run_keller("trace " + test::source_path(c.scene) + " -o " + out +
                                                 " --set output.xdmf=false" + c.overrides + extra);
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
  if (!extra.empty()) return t;
  std::vector<long> located;
  for (long i = 0; i < t.rows.rows(); ++i)
    if (const double k = t.rows(i, t.column("kind")); k != 0.0 && k != 1.0) located.push_back(i);
  if (t.status.find(step_floor) != std::string::npos && !located.empty() &&
      t.rows(located.back(), t.column("kind")) == 6.0)
    located.pop_back();
  const auto [cols, rows] = read_csv(test::source_path("tests/regression/references/hard/" + name + ".csv"));
  EXPECT_EQ(located.size(), rows.size()) << "number of located points changed";
  for (size_t k = 0; k < std::min(rows.size(), located.size()); ++k)
    for (size_t j = 0; j < cols.size(); ++j) {
      // Located points are converged to event_tolerance (1e-8) in the parameter and to Newton's
      // tolerance in the state; on this coarse mesh the continuation's path (where it factorises,
      // which steps it takes) moves them by less than that times the conditioning: 1e-6 relative.
      const double got = t.rows(located[k], t.column(cols[j])), want = rows[k][j];
      EXPECT_NEAR(got, want, 1e-6 * std::max(1.0, std::abs(want))) << cols[j] << " of located point " << k;
    }
  return t;
}

double last(const BranchTable& t, const std::string& col) { return t.rows(t.rows.rows() - 1, t.column(col)); }

// The parameter value of the located zero of monitor `name` (an event, or the end where the
// stop observable of that name crossed zero).
double located_zero(const BranchTable& t, const std::string& name) {
  for (long i = 0; i < t.rows.rows(); ++i) {
    const int k = static_cast<int>(t.rows(i, t.column("kind")));
    if ((k == 3 || k == 6) && std::abs(t.rows(i, t.column(name))) < 1e-6) return t.rows(i, t.column(t.parameter));
  }
  return NAN;
}

}  // namespace

// docs/collapsible.md: min m1 = 0 at Wi = 0.05043 (coarse mesh; M1 still has min m1 = 0.12 at Wi = 0.1)
TEST(HardCases, OldroydBUpToItsLimitingWiAtTheSmallestGamma) {
  const BranchTable t = trace("oldroyd_b_low_gamma");
  EXPECT_NE(t.status.find("min_m1"), std::string::npos) << t.status;
  EXPECT_NEAR(located_zero(t, "min_m1"), 0.05043, 5e-6);
}

// docs/collapsible.md: min m1 = 0 at Wi = 0.36339 at Gamma = 4.95e-4
TEST(HardCases, OldroydBUpToItsLimitingWiAtALargeGamma) {
  const BranchTable t = trace("oldroyd_b_high_gamma");
  EXPECT_NEAR(located_zero(t, "min_m1"), 0.36339, 5e-6);
}

// The log-conformation form passes the conformation form's limiting Wi (0.05043 on this mesh)
// with M positive definite by construction: min m1 > 0 at every point, to Wi = 0.08.
TEST(HardCases, LogConformationPastTheConformationFormsLimit) {
  const BranchTable t = trace("oldroyd_b_log_past_the_limit");
  EXPECT_NE(t.status.find("upper bound"), std::string::npos) << t.status;
  EXPECT_DOUBLE_EQ(last(t, "Wi"), 0.08);
  for (long i = 0; i < t.rows.rows(); ++i) EXPECT_GT(t.rows(i, t.column("min_m1")), 0.0) << "row " << i;
}

// docs/collapsible.md: FENE-P, b = 5, Gamma = 4.95e-4, to Wi = 8: min m1 = 0 at Wi = 0.69118 (an event), and
// the branch ends at the step floor where tr M reaches 3b at a conformation node, with tr M < 15
// at every point.
TEST(HardCases, FenePNearItsExtensibilityLimit) {
  const BranchTable t = trace("fene_p_b5");
  EXPECT_NEAR(located_zero(t, "min_m1"), 0.69118, 5e-6);
  for (int i = 0; i < t.rows.rows(); ++i) EXPECT_LT(t.rows(i, t.column("max_trM")), 15.0) << "row " << i;
  // the kernels refuse states with tr M >= 3b at any node: the branch ends at the step floor with
  // that reason instead of passing such a state off as a solution
  const bool at_bound = t.status.find("upper bound") != std::string::npos;
  const bool at_limit = t.status.find("3b") != std::string::npos;
  EXPECT_TRUE(at_bound || at_limit) << t.status;
  EXPECT_GT(last(t, "max_trM"), 14.0);  // at the spring's limit
}

// docs/collapsible.md: Owens, Gamma = 4.95e-4, to Wi = 5: min m1 = 0 at Wi = 1.7455 (an event), reaches Wi = 5
TEST(HardCases, OwensAtWi5) {
  const BranchTable t = trace("owens_wi5");
  EXPECT_NEAR(located_zero(t, "min_m1"), 1.7455, 5e-5);
  EXPECT_NE(t.status.find("upper bound"), std::string::npos) << t.status;
  EXPECT_DOUBLE_EQ(last(t, "Wi"), 5.0);
}

// docs/collapsible.md: the thinnest wall at the largest Gamma reaches t = 0.1 with a bulge dy_max = 1.41
TEST(HardCases, ThinnestWallAtTheLargestGamma) {
  const BranchTable t = trace("thinnest_wall_largest_gamma");
  EXPECT_DOUBLE_EQ(last(t, "t"), 0.1);
  EXPECT_NEAR(last(t, "dy_max"), 1.41, 5e-3);  // the wall bulges out by more than the channel width
}

// docs/collapsible.md: the strongest collapse (t to 0.1 at Gamma = 4.95e-5) reaches t = 0.1, gap 0.267
TEST(HardCases, StrongestCollapseAtTheSmallestGamma) {
  const BranchTable t = trace("strongest_collapse");
  EXPECT_DOUBLE_EQ(last(t, "t"), 0.1);
  EXPECT_NEAR(last(t, "gap_min"), 0.267, 5e-4);
}

// A first steady state that does not converge: the run says why, exits with 1 and writes nothing,
// both without a continuation path (start.homotopy = "off") and when every path also fails (one
// step allowed per stage). Newton alone fails here in 2 iterations; the default start reaches the
// state from Pe = 0 (FirstStateTest), so these runs must be told not to.
TEST(HardCases, AFirstStateThatFailsWritesNothing) {
  const HardCase c = hard_cases().at("owens_wi5");
  for (const std::string start : {" --set start.homotopy=off", " --set start.max_steps=1"}) {
    const std::string dir = test::scratch_dir("hard_first_state");
    const auto r = test::run_keller("trace " + test::source_path(c.scene) + " -o " + dir + "/x.h5" + c.overrides +
                                    " --set newton.max_iterations=2" + start);
    EXPECT_EQ(r.exit_code, 1) << start << "\n" << r.err;
    EXPECT_NE(r.err.find("the first steady state failed"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("no output written"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_empty(dir)) << start;
  }
}

// A restart from the last point of a branch that ended at the step floor: the restarted branch
// starts at that state and ends at the floor again, for the same reason, with no NaN and no
// inverted element.
TEST(HardCases, ARestartFromAStepFloorEndsThereAgain) {
  std::string from;
  const BranchTable first = trace("fene_p_b5", "", &from);
  ASSERT_NE(first.status.find(step_floor), std::string::npos) << first.status;
  const BranchTable again = trace("fene_p_b5", " --restart " + from + ":last");
  EXPECT_NEAR(again.rows(0, again.column("Wi")), last(first, "Wi"), 1e-12);
  EXPECT_NE(again.status.find(step_floor), std::string::npos) << again.status;
  EXPECT_NE(again.status.find("3b"), std::string::npos) << again.status;
}
