// Curves through the real driver: `keller trace SCENE --from BRANCH.h5:ROW --curve fold|hopf|event
// --free PARAMETER` continues the fold, Hopf point or event stored in a branch file in a second
// parameter; the curve agrees with the points of ordinary branches traced at its stored parameter
// values (or with the closed form), is a branch file like any other (killed, the same command
// continues it), and bad starts are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"
#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
using keller::test::rows_of_kind;
namespace fs = std::filesystem;

namespace {

const std::string kScene = "runs/scenes/bratu1d_shifted_fold_curve.toml";
const std::string kSmall = " --set bratu.intervals=64";

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

// The limiting-Wi curve of the collapsible channel (Oldroyd-B, t = 0.4) on the coarse mesh of the
// regression scenes: the zero of min m1 from the end of the Wi branch at Gamma = 4.95e-4,
// continued down in Gamma, agrees at Gamma = 4e-4, 3e-4, 2e-4, 1e-4 with the limiting Wi that
// ordinary Wi branches locate there (to 1e-8 in Wi) to 1e-6; the minimum's node moves along
// the curve, and every move is a located switch.
TEST(CurveCommand, LimitingWiCurveOfTheCollapsibleChannelMatchesWiBranches) {
  const std::string dir = test::scratch_dir("curve_limiting_wi");
  const std::string scene = test::source_path("runs/scenes/collapsible_oldroyd_b_wi_high_gamma.toml") +
                            " --set mesh.name=custom --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set "
                            "mesh.nx_downstream=5 --set mesh.ny_fluid=4 --set mesh.ny_solid=2";
  auto limiting_wi = [&](const std::string& out, const std::string& extra) {
    const auto r = test::run_keller("trace " + scene + extra + " -o " + out);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const BranchTable t = read_branch_table(out);
    const auto ends = rows_of_kind(t, PointKind::End);
    EXPECT_EQ(ends.size(), 1u);
    EXPECT_NEAR(t.rows(ends.back(), t.column("min_m1")), 0.0, 1e-9);
    return std::make_pair(ends.empty() ? -1L : ends.back(), ends.empty() ? NAN : t.rows(ends.back(), t.column("Wi")));
  };
  const auto [row, wi0] = limiting_wi(dir + "/wi.h5", "");
  ASSERT_GE(row, 0);
  auto r =
      test::run_keller("trace " + scene + " -o " + dir + "/curve.h5 --from " + dir + "/wi.h5:" + std::to_string(row) +
                       " --curve event --free Gamma --set continuation.direction=decrease --set "
                       "continuation.stops=[1e-4,2e-4,3e-4,4e-4] --set continuation.lower=5e-5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("left aside"), std::string::npos) << r.out;  // the scene's stop observable
  // the table on the terminal shows both parameters, Gamma and then Wi, the quantity the curve is for
  const size_t head = r.out.find("    row  kind");
  ASSERT_NE(head, std::string::npos) << r.out;
  const std::string header = r.out.substr(head, r.out.find('\n', head) - head);
  EXPECT_NE(header.find(" Gamma"), std::string::npos) << header;
  EXPECT_NE(header.find(" Wi "), std::string::npos) << header;
  EXPECT_LT(header.find(" Gamma"), header.find(" Wi ")) << header;
  const BranchTable curve = read_branch_table(dir + "/curve.h5");
  const int gamma = curve.column("Gamma"), wi = curve.column("Wi"), place = curve.column("place");
  EXPECT_NEAR(curve.rows(0, wi), wi0, 1e-9);
  const auto at = rows_of_kind(curve, PointKind::Requested);
  ASSERT_EQ(at.size(), 4u);
  for (long i : at) {
    const double g = curve.rows(i, gamma);
    const auto [end, w] =
        limiting_wi(dir + "/g" + std::to_string(i) + ".h5", " --set parameters.Gamma=" + std::to_string(g));
    std::cout << std::setprecision(12) << "Gamma = " << g << ": curve Wi = " << curve.rows(i, wi)
              << ", limiting Wi of the Wi branch " << w << "\n";
    EXPECT_NEAR(curve.rows(i, wi), w, 1e-6) << "Gamma = " << g;
    EXPECT_NEAR(curve.rows(i, curve.column("min_m1")), 0.0, 1e-9);
  }
  // the place changes only after a located switch (an event row: the curve's only events)
  const auto switches = rows_of_kind(curve, PointKind::Event);
  EXPECT_GE(switches.size(), 1u);
  for (long i = 1; i < curve.rows.rows(); ++i) {
    if (curve.rows(i, place) != curve.rows(i - 1, place)) {
      EXPECT_EQ(static_cast<int>(curve.rows(i - 1, curve.column("kind"))), static_cast<int>(PointKind::Event))
          << "row " << i;
    }
  }
  EXPECT_EQ(curve.rows(curve.rows.rows() - 1, gamma), 5e-5);
}

// The Hopf curve of the Brusselator through the driver: from the Hopf point located (with its
// eigenvector) on the b branch of runs/scenes/brusselator1d_hopf.toml at a = 2, continued in a from
// 1.5 to 3: every row on b = 1 + a^2, omega = a to 1e-8 (exact on the grid; Newton to 1e-12), its
// first Lyapunov coefficient (the bautin column) the closed form's, the stop a = 2.5 hit; a row that is not a Hopf
// point is refused, naming the Hopf rows; killed after its third point, the same command finishes the same curve.
TEST(CurveCommand, AHopfCurveFromAStoredHopfPointIsBEqualsOnePlusASquared) {
  const std::string dir = test::scratch_dir("curve_hopf");
  const std::string scene =
      test::source_path("runs/scenes/brusselator1d_hopf.toml") + " --set brusselator.intervals=32";
  auto r = test::run_keller("trace " + scene + " -o " + dir + "/branch.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto hopf = rows_of_kind(read_branch_table(dir + "/branch.h5"), PointKind::Hopf);
  ASSERT_EQ(hopf.size(), 1u);
  const std::string curve_args =
      " --curve hopf --free a --set stability.enabled=false --set continuation.lower=1.5 "
      "--set continuation.upper=3 --set continuation.stops=[2.5] --set "
      "newton.residual_tolerance=1e-12 -o " +
      dir + "/curve.h5";
  r = test::run_keller("trace " + scene + " --from " + dir + "/branch.h5:0" + curve_args);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("is not a located Hopf point"), std::string::npos) << r.err;
  r = test::run_keller("trace " + scene + " --from " + dir + "/branch.h5:" + std::to_string(hopf[0]) + curve_args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable t = read_branch_table(dir + "/curve.h5");
  const int a = t.column("a"), b = t.column("b"), omega = t.column("omega"), l1 = t.column("monitor:bautin");
  ASSERT_GT(t.rows.rows(), 4);
  for (long i = 0; i < t.rows.rows(); ++i) {
    const double ai = t.rows(i, a);
    EXPECT_NEAR(t.rows(i, b), 1.0 + ai * ai, 1e-8) << "a = " << ai;
    EXPECT_NEAR(t.rows(i, omega), ai, 1e-8) << "a = " << ai;
    // l1 of the uniform mode q = (q_u, 1) at each of the 33 nodes, |q_u|^2 = a^2 / (a^2 + 1) (the ODE's
    // l1 with q_v = 1, NormalFormsTest), divided by |q|^2 = 33 (2 a^2 + 1) / (a^2 + 1); measured to 1e-9
    const double unit_l1 = -(ai * ai + 2) / (2 * ai * 33.0 * (2 * ai * ai + 1));
    EXPECT_NEAR(t.rows(i, l1), unit_l1, 1e-6 * std::abs(unit_l1)) << "a = " << ai;
  }
  EXPECT_EQ(rows_of_kind(t, PointKind::Requested).size(), 1u);

  // killed mid-curve, the same command continues it (the borders set again at its last stored row)
  const std::string again = "trace " + scene + " --from " + dir + "/branch.h5:" + std::to_string(hopf[0]) +
                            curve_args.substr(0, curve_args.rfind(" -o ")) + " -o " + dir + "/killed.h5";
  r = test::run_keller(again, "KELLER_SIGNAL_AT=point:3 KELLER_SIGNAL=KILL");
  EXPECT_EQ(r.exit_code, -1) << r.out;
  ASSERT_TRUE(fs::exists(dir + "/killed.h5.part"));
  r = test::run_keller(again);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("continuing the unfinished curve"), std::string::npos) << r.out;
  const BranchTable finished = read_branch_table(dir + "/killed.h5");
  EXPECT_EQ(rows_of_kind(finished, PointKind::Requested).size(), 1u);
  for (long i = 0; i < finished.rows.rows(); ++i)
    EXPECT_NEAR(finished.rows(i, b), 1.0 + finished.rows(i, a) * finished.rows(i, a), 1e-8)
        << "a = " << finished.rows(i, a);
}

// Continuation in a law's constant: the limiting Wi of a Giesekus fluid against its mobility
// alpha, an event curve from the end of the Wi branch at alpha = 0.1 down to alpha = 0, where the
// law is Oldroyd-B's: there the curve's Wi is the Oldroyd-B branch's limiting Wi on the same
// (coarse) mesh, to 1e-6 (both are located zeros of min m1 to the corrector's tolerance; they
// agree to 1e-9), and min m1 = 0 at every point of the curve.
TEST(CurveCommand, LimitingWiAgainstGiesekusMobilityMeetsOldroydBAtZero) {
  const std::string dir = test::scratch_dir("curve_giesekus_alpha");
  const std::string mesh =
      " --set mesh.name=custom --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set mesh.nx_downstream=5 "
      "--set mesh.ny_fluid=4 --set mesh.ny_solid=2";
  auto end_of = [&](const std::string& scene, const std::string& out) {
    const auto r = test::run_keller("trace " + test::source_path("runs/scenes/" + scene) + mesh + " -o " + out);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const BranchTable t = read_branch_table(out);
    const auto ends = rows_of_kind(t, PointKind::End);
    EXPECT_EQ(ends.size(), 1u);
    EXPECT_NEAR(t.rows(ends.back(), t.column("min_m1")), 0.0, 1e-9);
    return t.rows(ends.back(), t.column("Wi"));
  };
  const double wi_giesekus = end_of("collapsible_giesekus_wi_high_gamma.toml", dir + "/wi.h5");
  const double wi_oldroyd_b = end_of("collapsible_oldroyd_b_wi_high_gamma.toml", dir + "/ob.h5");
  EXPECT_GT(wi_giesekus, wi_oldroyd_b * 1.2);  // shear thinning delays the loss of positive definiteness
  const auto r = test::run_keller("trace " + test::source_path("runs/scenes/collapsible_giesekus_wi_limit_alpha.toml") +
                                  mesh + " --from " + dir + "/wi.h5:end --curve event -o " + dir +
                                  "/curve.h5 --set continuation.direction=\"decrease\"");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable curve = read_branch_table(dir + "/curve.h5");
  const int alpha = curve.column("alpha"), wi = curve.column("Wi"), m1 = curve.column("min_m1");
  const long last = curve.rows.rows() - 1;
  EXPECT_NEAR(curve.rows(0, wi), wi_giesekus, 1e-9);
  EXPECT_NEAR(curve.rows(last, alpha), 0.0, 1e-12);
  EXPECT_NEAR(curve.rows(last, wi), wi_oldroyd_b, 1e-6);
  for (long i = 0; i <= last; ++i) EXPECT_NEAR(curve.rows(i, m1), 0.0, 1e-9) << "row " << i;
  std::cout << std::setprecision(12) << "limiting Wi: Giesekus alpha = 0.1 " << wi_giesekus << ", curve at alpha = 0 "
            << curve.rows(last, wi) << ", Oldroyd-B branch " << wi_oldroyd_b << "\n";
}

// A fold curve through a cusp, by the real driver: the imperfect pitchfork -u'' - lambda u + u^3 -
// eps = 0 (runs/scenes/pitchfork1d_trivial.toml, 16 intervals) traced in eps at lambda = 12 from u = 0
// meets a fold at eps = 1.11; continued in lambda (--curve fold --free lambda), it runs down into the cusp at
// u = 0, eps = 0, lambda = lambda_1, where the curve turns. There the cusp's normal form
// (NormalForms::cusp, /branch/normal_forms, type "cusp") has the grid's closed form: phi = the
// discrete sine mode v (unit 2-norm, positive), psi = -v (b = <psi, F_eps> = sum v > 0), h2 = 0
// (F_uu = 6 u phi^2 = 0 at u = 0), c = <psi, F_uuu[v, v, v]> = -6 sum v^4 = -9 / n, and the branch
// through it at lambda_1 is eps = cubic A^3 with cubic = -c / (6 b) = sum v^4 / sum v (projecting
// F(A v) = 0 on v). sum v = cot(pi / 2n) / sqrt(n / 2). Third derivatives by differences (1e-6
// relative) and the cusp located to 1e-10 in lambda (u ~ 1e-5): agreement to 1e-5 relative.
TEST(CurveCommand, ACuspOfTheImperfectPitchforkHasTheGridsCubicCoefficient) {
  const std::string dir = test::scratch_dir("curve_cusp");
  const std::string scene = test::source_path("runs/scenes/pitchfork1d_trivial.toml") +
                            " --set pitchfork.intervals=16 --set parameters.lambda=12.0 --set stability.enabled=false";
  auto r = test::run_keller("trace " + scene +
                            " --set continuation.parameter=\"eps\" --set continuation.lower=-3.0 "
                            "--set continuation.upper=3.0 --set continuation.initial_step=0.01 "
                            "--set continuation.max_step=0.05 -o " +
                            dir + "/eps.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto folds = rows_of_kind(read_branch_table(dir + "/eps.h5"), PointKind::Fold);
  ASSERT_EQ(folds.size(), 1u);
  r = test::run_keller("trace " + scene + " --from " + dir + "/eps.h5:fold1 --curve fold --free lambda " +
                       "--set continuation.parameter=\"lambda\" --set continuation.lower=5.0 " +
                       "--set continuation.upper=14.0 --set continuation.direction=\"decrease\" -o " + dir +
                       "/curve.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("cusp: c "), std::string::npos) << r.out;

  const BranchTable t = read_branch_table(dir + "/curve.h5");
  H5File f(dir + "/curve.h5", H5File::Mode::Read);
  long rows = 0, cols = 0;
  const std::vector<double> nf = f.read_matrix("/branch/normal_forms", &rows, &cols);
  const std::string columns = f.read_string_attribute("/branch/normal_forms", "columns");
  auto column = [&](const std::string& name) {  // index in "row,kind,type,exact,a,b,c,curvature,cubic,..."
    int k = 0;
    size_t at = 0;
    while (true) {
      const size_t end = columns.find(',', at);
      if (columns.substr(at, end - at) == name) return k;
      if (end == std::string::npos) return -1;
      at = end + 1;
      ++k;
    }
  };
  ASSERT_EQ(rows, 1);  // the cusp; the curve's turn in lambda is no fold of a branch
  const auto at = [&](const std::string& name) { return nf[static_cast<size_t>(column(name))]; };
  const long row = static_cast<long>(at("row"));
  EXPECT_EQ(t.rows(row, t.column("kind")), static_cast<double>(PointKind::Event));
  EXPECT_EQ(normal_form_types()[static_cast<size_t>(at("type"))], "cusp");
  const double n = 16, lambda1 = 4 * n * n * std::pow(std::sin(std::numbers::pi / (2 * n)), 2);
  EXPECT_NEAR(t.rows(row, t.column("lambda")), lambda1, 1e-8);
  const double c = -9.0 / n, b = 1.0 / std::tan(std::numbers::pi / (2 * n)) / std::sqrt(n / 2);
  EXPECT_NEAR(at("b"), b, 1e-8 * b);
  EXPECT_NEAR(at("c"), c, 1e-5 * std::abs(c));
  EXPECT_NEAR(at("cubic"), -c / (6 * b), 1e-5 * std::abs(c / (6 * b)));
  EXPECT_NEAR(at("a"), 0.0, 1e-4);  // 6 u at the located cusp, u ~ 1e-5
}
