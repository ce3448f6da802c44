// `keller trace --from BRANCH.h5:hopf1 --orbit` through the real driver on the 1D Brusselator
// (docs/periodic_orbits.md): its uniform orbits are the Brusselator ODE's, known from an independent
// RK4 integration (a = 2, b = 5.5: T = 3.982851017, v from 1.3045647 to 4.8342820); near the Hopf
// point the amplitude follows the normal form's sqrt law; a row that is not a Hopf point, a
// problem without dynamics, --orbit without --from, and --switch at a row that is not a period
// doubling are refused before any work (the switch itself: tests/python/test_orbits.py); a killed
// branch is continued by the same command.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "continuation/engine/BranchPoint.hpp"
#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
using keller::test::rows_of_kind;
namespace fs = std::filesystem;

namespace {

const std::string kScene = "runs/scenes/brusselator1d_hopf.toml";

// The Hopf branch of the scene on 16 intervals, traced once per test binary into `dir`.
std::string hopf_branch(const std::string& dir) {
  const std::string out = dir + "/branch.h5";
  if (!fs::exists(out)) {
    const auto r = test::run_keller("trace " + test::source_path(kScene) + " --set brusselator.intervals=16 -o " + out);
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
  return out;
}

std::string orbit_command(const std::string& branch, const std::string& from, const std::string& out,
                          const std::string& extra = "") {
  return "trace " + test::source_path(kScene) +
         " --set brusselator.intervals=16 --set stability.enabled=false --from " + branch + ":" + from + " --orbit " +
         extra + " -o " + out;
}

// A number of /branch/normal_forms's only row by its column name.
double normal_form(const std::string& file, const std::string& name) {
  H5File f(file, H5File::Mode::Read);
  long rows = 0, cols = 0;
  const std::vector<double> nf = f.read_matrix("/branch/normal_forms", &rows, &cols);
  std::stringstream columns(f.read_string_attribute("/branch/normal_forms", "columns"));
  EXPECT_EQ(rows, 1);
  size_t k = 0;
  for (std::string column; std::getline(columns, column, ','); ++k)
    if (column == name) return nf[k];
  ADD_FAILURE() << "no normal-form column " << name;
  return 0.0;
}

}  // namespace

// The stop at b = 5.5 against the ODE's orbit: SDIRK4 at the default rtol 1e-6 errs by 8.0e-7 in
// the period on the stop's own grid (1.09e-6 on a neighbour's grid 0.1 away, which the stop used
// before it was corrected again on its own), and the amplitude of v, from the extreme samples
// refined by parabolas over about 60 steps a period, by about 5e-5 relative (measured 3.4e-5).
TEST(OrbitCommand, BrusselatorBranchFromItsHopfPointAgainstTheOdeOrbit) {
  const std::string dir = test::scratch_dir("orbit_brusselator");
  const std::string branch = hopf_branch(dir);
  const auto r = test::run_keller(
      orbit_command(branch, "hopf1", dir + "/orbits.h5",
                    "--set continuation.upper=5.7 --set continuation.stops=[5.5] --set orbit.start_distance=0.005"));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const BranchTable t = read_branch_table(dir + "/orbits.h5");
  const auto stops = rows_of_kind(t, PointKind::Requested);
  ASSERT_EQ(stops.size(), 1u);
  const long s = stops[0];
  EXPECT_NEAR(t.rows(s, t.column("b")), 5.5, 1e-12);
  EXPECT_NEAR(t.rows(s, t.column("period")) / 3.982851017, 1.0, 1e-6);
  EXPECT_NEAR(t.rows(s, t.column("amplitude")) / (4.8342820 - 1.3045647), 1.0, 2e-4);
  // a stable orbit: every multiplier but the trivial one inside the unit circle; the trivial one 1
  // to the integrator's error (1e-5 at rtol 1e-6: docs/periodic_orbits.md)
  EXPECT_NEAR(t.rows(s, t.column("mu1_re")), 1.0, 5e-5);
  EXPECT_LT(std::hypot(t.rows(s, t.column("mu2_re")), t.rows(s, t.column("mu2_im"))), 1.0);
  // the first two orbits at d = 0.005 and 0.01 past b_H = 5: amplitude (max - min of the unknown
  // that varies most) = 2 amplitude_coefficient sqrt(d) (1 + O(d)), measured 0.2% and 0.4% off;
  // the period 2 pi / omega + O(d)
  // every row's amplitudes (of the states and of the observables), growing along the branch
  for (long i = 1; i < t.rows.rows(); ++i) {
    EXPECT_GT(t.rows(i, t.column("amplitude")), t.rows(i - 1, t.column("amplitude"))) << "row " << i;
    EXPECT_GT(t.rows(i, t.column("amplitude:u_mean")), t.rows(i - 1, t.column("amplitude:u_mean"))) << "row " << i;
  }
  const double coefficient = normal_form(branch, "amplitude_coefficient"), omega = normal_form(branch, "omega");
  for (long row = 0; row < 2; ++row) {
    const double d = t.rows(row, t.column("b")) - 5.0;
    EXPECT_NEAR(d, 0.005 * (row + 1), 1e-12);
    EXPECT_NEAR(t.rows(row, t.column("amplitude")) / (2.0 * coefficient * std::sqrt(d)), 1.0, 0.01) << d;
    EXPECT_NEAR(t.rows(row, t.column("period")) / (2.0 * std::numbers::pi / omega), 1.0, 2.0 * d) << d;
  }
}

TEST(OrbitCommand, BadRequestsAreRefusedBeforeAnyWork) {
  const std::string dir = test::scratch_dir("orbit_refusals");
  const std::string branch = hopf_branch(dir);
  auto r = test::run_keller(orbit_command(branch, "0", dir + "/a.h5"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("row 0 is not a located Hopf point"), std::string::npos) << r.err;
  r = test::run_keller("trace " + test::source_path(kScene) + " --orbit -o " + dir + "/b.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--orbit starts at a located Hopf point"), std::string::npos) << r.err;
  // Stokes flow (Re = 0) has B = 0: no dynamics, whatever row it starts from (--force lets a row
  // that is not a Hopf point through to that check)
  const std::string stokes = test::source_path("runs/scenes/channel_stokes.toml") +
                             " --set mesh.name=\"M1\" --set continuation.parameter=\"Gamma\"";
  r = test::run_keller("trace " + stokes + " --set continuation.max_steps=1 -o " + dir + "/stokes.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_keller("trace " + stokes + " --from " + dir + "/stokes.h5:0 --orbit --force -o " + dir + "/c.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the mass matrix B is zero"), std::string::npos) << r.err;
  r = test::run_keller(orbit_command(branch, "hopf1", dir + "/d.h5", "--curve hopf"));
  EXPECT_EQ(r.exit_code, 2);
  // --switch with --orbit: a located period doubling of an orbit branch, and not with --from
  const std::string doubled = "trace " + test::source_path(kScene) +
                              " --set brusselator.intervals=16 --set stability.enabled=false --orbit --switch " +
                              branch + ":hopf1 -o " + dir + "/e.h5";
  r = test::run_keller(doubled);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("is not a located period doubling"), std::string::npos) << r.err;
  r = test::run_keller(orbit_command(branch, "hopf1", dir + "/f.h5", "--switch " + branch + ":hopf1"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("one of them"), std::string::npos) << r.err;
  for (const char* f : {"/a.h5", "/b.h5", "/c.h5", "/d.h5", "/e.h5", "/f.h5"}) {
    EXPECT_FALSE(fs::exists(dir + f)) << f;
    EXPECT_FALSE(fs::exists(dir + f + std::string(".part"))) << f;
  }
}

// Killed after its fourth orbit, the same command continues the branch from its last two rows and
// ends where an uninterrupted run ends.
TEST(OrbitCommand, AKilledBranchIsContinuedByTheSameCommand) {
  const std::string dir = test::scratch_dir("orbit_killed");
  const std::string branch = hopf_branch(dir);
  const std::string command = orbit_command(branch, "hopf1", dir + "/orbits.h5", "--set continuation.upper=5.4");
  auto r = test::run_keller(command, "KELLER_SIGNAL_AT=point:4 KELLER_SIGNAL=KILL");
  EXPECT_EQ(r.exit_code, -1) << r.out;
  ASSERT_TRUE(fs::exists(dir + "/orbits.h5.part"));
  r = test::run_keller(command);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("continuing the unfinished orbit branch"), std::string::npos) << r.out;
  const BranchTable t = read_branch_table(dir + "/orbits.h5");
  const long last = t.rows.rows() - 1;
  EXPECT_GT(t.rows(last, t.column("b")), 5.4);
  for (long i = 1; i <= last; ++i) {
    EXPECT_EQ(t.rows(i, t.column("row")), static_cast<double>(i));
    EXPECT_GT(t.rows(i, t.column("b")), t.rows(i - 1, t.column("b"))) << "row " << i;
  }
}

// From a keller evolve run on its limit cycle (--from RUN.h5): the orbit through its last state at
// its b, with the period estimated from the run's crossings. At b = 5.5 the uniform orbit is the
// ODE's on any number of intervals (4 here): its period to 1e-6, as from the Hopf point. A scene
// at another a, and a run too short to hold three periods in its second half, are refused before
// any work, with nothing written.
TEST(OrbitCommand, StartsFromAnEvolveRunOnItsLimitCycle) {
  const std::string dir = test::scratch_dir("orbit_from_evolve");
  const std::string evolve = test::source_path("runs/scenes/brusselator1d_evolve.toml");
  const std::string common = " --set brusselator.intervals=4 --set parameters.b=5.5";
  auto integrate = [&](const std::string& out, double t_end) {
    const auto r = test::run_keller("evolve " + evolve + common + " --set evolve.t_end=" + std::to_string(t_end) +
                                    " --set evolve.amplitude=1e-2 --set evolve.relative_tolerance=1e-5"
                                    " --set evolve.method=\\\"sdirk4\\\" -o " +
                                    out);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  };
  integrate(dir + "/run.h5", 100.0);
  const std::string trace = "trace " + test::source_path(kScene) + common +
                            " --set stability.enabled=false --set continuation.upper=5.6 --orbit --from ";
  const auto r = test::run_keller(trace + dir + "/run.h5 -o " + dir + "/orbits.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("from the crossings of"), std::string::npos) << r.out;
  const BranchTable t = read_branch_table(dir + "/orbits.h5");
  ASSERT_GE(t.rows.rows(), 3);
  EXPECT_NEAR(t.rows(0, t.column("b")), 5.5, 1e-12);
  EXPECT_NEAR(t.rows(0, t.column("period")) / 3.982851017, 1.0, 1e-6);
  EXPECT_GT(t.rows(t.rows.rows() - 1, t.column("b")), 5.5);  // continued in the direction asked

  const auto other = test::run_keller(trace + dir + "/run.h5 --set parameters.a=2.5 -o " + dir + "/other.h5");
  EXPECT_EQ(other.exit_code, 2) << other.out << other.err;
  EXPECT_NE(other.err.find("a = 2"), std::string::npos) << other.err;
  EXPECT_FALSE(fs::exists(dir + "/other.h5"));
  EXPECT_FALSE(fs::exists(dir + "/other.h5.part"));

  integrate(dir + "/short.h5", 5.0);
  const auto short_run = test::run_keller(trace + dir + "/short.h5 -o " + dir + "/short_orbits.h5");
  EXPECT_EQ(short_run.exit_code, 2) << short_run.out << short_run.err;
  EXPECT_NE(short_run.err.find("no observable oscillates"), std::string::npos) << short_run.err;
  EXPECT_FALSE(fs::exists(dir + "/short_orbits.h5"));
}

// keller export ORBITS.h5 --orbit ROW: the orbit of a row integrated again over its period, its
// fields at frames + 1 evenly spaced times (the Brusselator's profile of x, u, v; it has no mesh,
// so no XDMF animation, which the fields of a problem with one get). The last frame is the
// first again: the orbit is periodic to Newton's tolerance and the new grid's error (SDIRK4 at
// rtol 1e-6 over a period: 1e-5 of v allowed). Not an orbit branch, or a row without a stored
// orbit, is refused with nothing written.
TEST(OrbitCommand, ExportsAnOrbitAsAnAnimation) {
  const std::string dir = test::scratch_dir("orbit_export");
  const std::string branch = hopf_branch(dir);
  const auto r = test::run_keller(orbit_command(branch, "hopf1", dir + "/orbits.h5",
                                                "--set continuation.upper=5.3 --set continuation.stops=[5.2]"));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto e = test::run_keller("export " + dir + "/orbits.h5 --orbit stop1 --frames 12");
  ASSERT_EQ(e.exit_code, 0) << e.out << e.err;
  const std::string out = dir + "/orbits-orbitstop1.h5";
  ASSERT_TRUE(fs::exists(out));
  EXPECT_FALSE(fs::exists(dir + "/orbits-orbitstop1.xdmf"));
  H5File f(out, H5File::Mode::Read);
  for (int k = 0; k <= 12; ++k) EXPECT_TRUE(f.exists("/orbit/fields/" + std::to_string(k))) << k;
  EXPECT_FALSE(f.exists("/orbit/fields/13"));
  long n0 = 0, c0 = 0, n12 = 0, c12 = 0;
  const std::vector<double> v0 = f.read_matrix("/orbit/fields/0/profile", &n0, &c0);
  const std::vector<double> v12 = f.read_matrix("/orbit/fields/12/profile", &n12, &c12);
  ASSERT_EQ(v0.size(), v12.size());
  ASSERT_FALSE(v0.empty());
  double diff = 0.0, size = 0.0;
  for (size_t i = 0; i < v0.size(); ++i) {
    diff = std::max(diff, std::abs(v12[i] - v0[i]));
    size = std::max(size, std::abs(v0[i]));
  }
  EXPECT_LT(diff, 1e-5 * size);
  const std::vector<double> v6 = f.read_matrix("/orbit/fields/6/profile", &n12, &c12);
  double moved = 0.0;  // half a period on, the orbit is elsewhere
  for (size_t i = 0; i < v0.size(); ++i) moved = std::max(moved, std::abs(v6[i] - v0[i]));
  EXPECT_GT(moved, 0.1);

  // without --frames, the branch scene's orbit.frames (40 by default): 41 frames
  const auto by_scene = test::run_keller("export " + dir + "/orbits.h5 --orbit 1");
  ASSERT_EQ(by_scene.exit_code, 0) << by_scene.err;
  H5File g(dir + "/orbits-orbit1.h5", H5File::Mode::Read);
  EXPECT_TRUE(g.exists("/orbit/fields/40"));
  EXPECT_FALSE(g.exists("/orbit/fields/41"));

  const auto not_orbits = test::run_keller("export " + branch + " --orbit 1");
  EXPECT_EQ(not_orbits.exit_code, 2) << not_orbits.err;
  EXPECT_NE(not_orbits.err.find("not an orbit branch"), std::string::npos) << not_orbits.err;
  EXPECT_FALSE(fs::exists(dir + "/branch-orbit1.h5"));
}

// The collapsible channel's self-excited oscillation on the coarse mesh (runs/scenes/
// orbit_collapsible_newtonian.toml, docs/periodic_orbits.md): its first two orbits from the Hopf
// point (Re_H = 99.264 at Gamma = 9e-5, supercritical), at d = Re - Re_H = 0.5 and 1.
// - Against the normal form: the period's and gap_min amplitude's relative differences from 2 pi /
//   omega and 2 a sqrt(d) are O(d) (measured +0.171%, +0.341% and -0.69%, -1.37%): each at most
//   1% and 3% of d, and the second twice the first (1.7 to 2.3; measured 1.99 and 1.98). The
//   amplitude multiplier is exp(-2 g' d T) to its next order, O(d^2) (measured 2e-4 and 5e-4; the
//   computed multipliers of one orbit scatter by 2e-4 from run to run), so to 1e-3; the trivial
//   one is 1 to 1e-3 (measured up to 2e-4). Both orbits stable.
// - Against keller evolve: one period from the orbit at d = 1 (SDIRK4, rtol 1e-8) returns gap_min
//   to its start to 1e-5 of the amplitude (the orbit's own grid errs by about 1e-6 of the period,
//   a phase error of 2 pi 1e-6 of the amplitude), and its max - min over the period (666 samples,
//   not refined: 1e-5) is the orbit's amplitude to 1e-4.
// - keller export --orbit: fields at 4 + 1 frames with the XDMF animation of a problem with a mesh,
//   the last frame the first again (the export's own grid at rtol 1e-6: 1e-4 of the largest
//   displacement allowed, measured 3e-8).
TEST(OrbitCommand, TheChannelsOscillationOnTheCoarseMeshAgainstItsNormalFormAndEvolve) {
  const std::string dir = test::scratch_dir("orbit_channel");
  const std::string scene = test::source_path("runs/scenes/orbit_collapsible_newtonian.toml");
  auto r = test::run_keller("trace " + scene + " --set continuation.upper=100.0 --set continuation.stops=[] -o " + dir +
                            "/hopf.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string hopf = dir + "/hopf.h5";
  r = test::run_keller("trace " + scene + " --from " + hopf +
                       ":hopf1 --orbit --set stability.enabled=false --set continuation.upper=100.2 "
                       "--set continuation.stops=[] --set orbit.multipliers=2 -o " +
                       dir + "/orbits.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const BranchTable t = read_branch_table(dir + "/orbits.h5");
  ASSERT_EQ(t.rows.rows(), 2);
  const BranchTable h = read_branch_table(hopf);
  const long hopf_row = rows_of_kind(h, PointKind::Hopf).at(0);
  const double re_h = h.rows(hopf_row, h.column("Re"));
  const double omega = normal_form(hopf, "omega"), g = normal_form(hopf, "growth_rate_derivative"),
               a = normal_form(hopf, "amplitude:gap_min");
  EXPECT_NEAR(re_h, 99.264, 1e-3);
  double period_dev[2], amplitude_dev[2];
  for (long row = 0; row < 2; ++row) {
    const double d = t.rows(row, t.column("Re")) - re_h, T = t.rows(row, t.column("period"));
    EXPECT_NEAR(d, 0.5 * (row + 1), 1e-9);
    period_dev[row] = T / (2.0 * std::numbers::pi / omega) - 1.0;
    amplitude_dev[row] = t.rows(row, t.column("amplitude:gap_min")) / (2.0 * a * std::sqrt(d)) - 1.0;
    EXPECT_LT(std::abs(period_dev[row]), 0.01 * d) << d;
    EXPECT_LT(std::abs(amplitude_dev[row]), 0.03 * d) << d;
    const std::complex<double> mu1(t.rows(row, t.column("mu1_re")), t.rows(row, t.column("mu1_im"))),
        mu2(t.rows(row, t.column("mu2_re")), t.rows(row, t.column("mu2_im")));
    EXPECT_NEAR(std::abs(mu1 - 1.0), 0.0, 1e-3) << d;
    EXPECT_NEAR(std::abs(mu2 - std::exp(-2.0 * g * d * T)), 0.0, 1e-3) << d;
    EXPECT_LT(std::abs(mu2), 1.0) << d;
  }
  EXPECT_NEAR(period_dev[1] / period_dev[0], 2.0, 0.3);
  EXPECT_NEAR(amplitude_dev[1] / amplitude_dev[0], 2.0, 0.3);

  // one period of keller evolve from the orbit at d = 1
  {
    std::ofstream ev(dir + "/evolve.toml");
    ev << "[problem]\ntype = \"collapsible-channel\"\n[fluid]\nmodel = \"newtonian\"\n"
          "[mesh]\nname = \"custom\"\nnx_upstream = 5\nnx_deformable = 10\nnx_downstream = 5\nny_fluid = 4\n"
          "ny_solid = 2\n[dynamics]\nmass_matrix = \"moving-wall\"\n"
          "[parameters]\nRe = 0.01\nGamma = 9e-5\nt = 0.4\nPe = 0.04\n"
          "[evolve]\nmethod = \"sdirk4\"\nrelative_tolerance = 1e-8\nabsolute_tolerance = 1e-12\n"
          "perturbation = \"none\"\n";
  }
  const double T = t.rows(1, t.column("period"));
  r = test::run_keller("evolve " + dir + "/evolve.toml --restart " + dir +
                       "/orbits.h5:1 --set evolve.t_end=" + fmt::format("{:.17g}", T) + " -o " + dir + "/evolve.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const TimeTable e = read_time_table(dir + "/evolve.h5");
  ASSERT_GT(e.rows.rows(), 100);
  const Eigen::VectorXd gap = e.rows.col(e.column("gap_min"));
  const double amplitude = t.rows(1, t.column("amplitude:gap_min"));
  EXPECT_NEAR(e.rows(e.rows.rows() - 1, e.column("t")), T, 1e-9 * T);
  EXPECT_LT(std::abs(gap[gap.size() - 1] - gap[0]), 1e-5 * amplitude);
  EXPECT_NEAR((gap.maxCoeff() - gap.minCoeff()) / amplitude, 1.0, 1e-4);

  // the orbit as an animation, XDMF included
  r = test::run_keller("export " + dir + "/orbits.h5 --orbit 1 --frames 4");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  ASSERT_TRUE(fs::exists(dir + "/orbits-orbit1.xdmf"));
  std::ifstream xdmf(dir + "/orbits-orbit1.xdmf");
  const std::string text((std::istreambuf_iterator<char>(xdmf)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("CollectionType=\"Temporal\""), std::string::npos);
  EXPECT_NE(text.find("orbits-orbit1.h5:/orbit/fields/4/xdmf/displacement_vector"), std::string::npos);
  size_t times = 0;
  for (size_t at = text.find("<Time "); at != std::string::npos; at = text.find("<Time ", at + 1)) ++times;
  EXPECT_EQ(times, 5u);
  H5File f(dir + "/orbits-orbit1.h5", H5File::Mode::Read);
  EXPECT_FALSE(f.exists("/orbit/fields/5"));
  long n = 0, c = 0;
  const std::vector<double> first = f.read_matrix("/orbit/fields/0/displacement", &n, &c),
                            last = f.read_matrix("/orbit/fields/4/displacement", &n, &c),
                            half = f.read_matrix("/orbit/fields/2/displacement", &n, &c);
  ASSERT_EQ(first.size(), last.size());
  double size = 0.0, back = 0.0, moved = 0.0;
  for (size_t i = 0; i < first.size(); ++i) {
    size = std::max(size, std::abs(first[i]));
    back = std::max(back, std::abs(last[i] - first[i]));
    moved = std::max(moved, std::abs(half[i] - first[i]));
  }
  EXPECT_LT(back, 1e-4 * size);   // measured 3e-8 of it
  EXPECT_GT(moved, 0.05 * size);  // half a period on the wall is elsewhere (measured 0.08)
}

// A study of orbit branches (task = "orbit"): one `keller trace --orbit` per case from the case's
// located Hopf point, here the Brusselator's at a = 2 and a = 1.5 (b_H = 1 + a^2, omega = a). The
// collected orbit at each case's stop b = b_H + 0.012 is that case's: its period 2 pi / a + O(d)
// (the two differ by a third, so a start taken from the wrong case shows), its amplitude the normal
// form's 2 c sqrt(d) to 1% as the command's own orbits (measured: period +0.34% and +0.18%,
// amplitude +0.44% and +0.30%). An orbit study
// without a start, or with [stability] on, stops before any task with the key named.
TEST(OrbitCommand, AStudyOfOrbitBranchesFromTheHopfPointsOfItsCases) {
  const std::string dir = test::scratch_dir("orbit_study");
  const std::string branch2 = hopf_branch(dir), branch15 = dir + "/branch15.h5";
  auto r = test::run_keller("trace " + test::source_path(kScene) +
                            " --set brusselator.intervals=16 --set parameters.a=1.5 -o " + branch15);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const double d = 0.012;
  const auto write_study = [&](const std::string& name, const std::string& extra, bool starts) {
    std::ofstream s(dir + "/" + name + ".toml");
    s << "[study]\nscene = \"" << test::source_path(kScene) << "\"\ntask = \"orbit\"\n"
      << "[set]\n\"brusselator.intervals\" = 16\n\"orbit.start_distance\" = 0.005\n"
      << extra << "\n";
    for (const auto& [a, file] : {std::pair{2.0, branch2}, std::pair{1.5, branch15}}) {
      s << fmt::format(
          "[[cases]]\n\"parameters.a\" = {}\n\"continuation.upper\" = {:.17g}\n"
          "\"continuation.stops\" = [{:.17g}]\n",
          a, 1.0 + a * a + 2.0 * d, 1.0 + a * a + d);
      if (starts) s << "start = \"" << file << ":hopf1\"\n";
    }
    s << "[collect]\nstops = [\"period\", \"amplitude\"]\n";
    return dir + "/" + name + ".toml";
  };
  r = test::run_keller("study " + write_study("orbits", "\"stability.enabled\" = false", true) + " --jobs 1 -o " + dir +
                       "/orbits");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto rows = test::read_table(dir + "/orbits/orbits.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    SCOPED_TRACE(row.at("name"));
    EXPECT_EQ(row.at("status"), "done");
    const double a = std::stod(row.at("parameters.a"));
    const std::string at = fmt::format("@{}", 1.0 + a * a + d);  // the case's stop
    EXPECT_NEAR(std::stod(row.at("period" + at)) / (2.0 * std::numbers::pi / a), 1.0, 2.0 * d);
    const double c = normal_form(a == 2.0 ? branch2 : branch15, "amplitude_coefficient");
    EXPECT_NEAR(std::stod(row.at("amplitude" + at)) / (2.0 * c * std::sqrt(d)), 1.0, 0.01);
  }
  r = test::run_keller("study " + write_study("no_start", "\"stability.enabled\" = false", false) + " -o " + dir +
                       "/no_start");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("an orbit branch starts at a located Hopf point: set study.start"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/no_start/tasks"));
  r = test::run_keller("study " + write_study("stability", "", true) + " -o " + dir + "/stability");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("key 'stability.enabled'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/stability/tasks"));
}
