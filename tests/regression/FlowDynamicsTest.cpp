// Two-parameter curves and time integration on a `flow` (a mesh from Gmsh), through the real
// driver, on coarse meshes of the shipped geometries: the limiting-Wi curve of the contraction in
// beta agrees with the limiting Wi that ordinary Wi branches locate at its stored beta values; a
// perturbed Navier-Stokes flow through the stenosis returns to the steady state `solve` computes,
// its perturbation decaying at the least stable eigenvalue `solve` computes; a branch in Re that
// starts from Stokes flow has inertia; a Stokes flow (Newtonian, Re = 0), which has no time
// derivative, is refused by evolve and by a spectrum, naming parameters.Re.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"
#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
using keller::test::rows_of_kind;
namespace fs = std::filesystem;

namespace {

// A 1D dataset as a vector.
Vector read_state(const H5File& f, const std::string& dataset) {
  long rows = 0, cols = 0;
  const std::vector<double> v = f.read_matrix(dataset, &rows, &cols);
  return Eigen::Map<const Vector>(v.data(), static_cast<long>(v.size()));
}

// The state stored last in a time-series file (the run's end).
Vector last_saved_state(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  long rows = 0, cols = 0;
  const std::vector<double> s = f.read_matrix("/evolve/solutions", &rows, &cols);
  Vector u(cols);
  for (long j = 0; j < cols; ++j) u[j] = s[static_cast<size_t>((rows - 1) * cols + j)];
  return u;
}

}  // namespace

// runs/scenes/flow_contraction_limiting_wi.toml (Oldroyd-B, conformation form, a coarse mesh of
// 2621 unknowns): the Wi branch at beta = 1/9 ends where min_m1 = 0; the event curve from that
// end, continued in beta to 0.5 with stops at 0.2, 0.3, 0.4, agrees there with the ends of Wi
// branches traced at those beta. Both are solutions of F = 0, min_m1 = 0 at the same beta, each to
// Newton's tolerance (|F| ~ 1e-11) and |min_m1| < 1e-9 (asserted), and d min_m1 / d Wi is about -1.4
// at the end, so they agree to about 1e-9 in Wi (measured: 1.4e-10): 1e-8 allowed. The node where min m1 sits moves
// along the curve only at a located switch.
TEST(FlowCurve, LimitingWiCurveInBetaMatchesTheEndsOfWiBranches) {
  const std::string dir = test::scratch_dir("flow_curve");
  const std::string scene = test::source_path("runs/scenes/flow_contraction_limiting_wi.toml");
  auto limiting_wi = [&](const std::string& out, const std::string& extra) {
    const auto r = test::run_keller("trace " + scene + extra + " -o " + out);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const BranchTable t = read_branch_table(out);
    const auto ends = rows_of_kind(t, PointKind::End);
    EXPECT_EQ(ends.size(), 1u);
    if (ends.empty()) return std::make_pair(-1L, static_cast<double>(NAN));
    EXPECT_NEAR(t.rows(ends.back(), t.column("min_m1")), 0.0, 1e-9);
    return std::make_pair(ends.back(), t.rows(ends.back(), t.column("Wi")));
  };
  const auto [row, wi0] = limiting_wi(dir + "/wi.h5", "");
  ASSERT_GE(row, 0);
  auto r = test::run_keller("trace " + scene + " -o " + dir + "/curve.h5 --from " + dir + "/wi.h5:end" +
                            " --curve event --free beta --set continuation.upper=0.5 --set "
                            "continuation.stops=[0.2,0.3,0.4]");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable curve = read_branch_table(dir + "/curve.h5");
  EXPECT_EQ(curve.parameter, "beta");
  const int beta = curve.column("beta"), wi = curve.column("Wi"), place = curve.column("place");
  EXPECT_NEAR(curve.rows(0, wi), wi0, 1e-9);
  const auto at = rows_of_kind(curve, PointKind::Requested);
  ASSERT_EQ(at.size(), 3u);
  for (long i : at) {
    const double b = curve.rows(i, beta);
    const auto [end, w] =
        limiting_wi(dir + "/b" + std::to_string(i) + ".h5", " --set parameters.beta=" + std::to_string(b));
    std::cout << std::setprecision(12) << "beta = " << b << ": curve Wi = " << curve.rows(i, wi)
              << ", the Wi branch's end " << w << "\n";
    EXPECT_NEAR(curve.rows(i, wi), w, 1e-8) << "beta = " << b;
    EXPECT_NEAR(curve.rows(i, curve.column("min_m1")), 0.0, 1e-9);
  }
  for (long i = 0; i < curve.rows.rows(); ++i) EXPECT_NEAR(curve.rows(i, curve.column("min_m1")), 0.0, 1e-9);
  for (long i = 1; i < curve.rows.rows(); ++i)
    if (curve.rows(i, place) != curve.rows(i - 1, place)) {
      EXPECT_EQ(static_cast<int>(curve.rows(i - 1, curve.column("kind"))), static_cast<int>(PointKind::Event))
          << "row " << i;
    }
  EXPECT_EQ(curve.rows(curve.rows.rows() - 1, beta), 0.5);
}

namespace {

// The steady state and spectrum of runs/scenes/flow_stenosis_stability.toml (Navier-Stokes, Re = 10, 643
// unknowns), by `keller solve`: the state and the least stable eigenvalue (sigma_re, sigma_im).
struct Steady {
  Vector u;
  double sigma_re = NAN, sigma_im = NAN;
};

Steady solve_stenosis(const std::string& dir) {
  const auto r = test::run_keller("solve " + test::source_path("runs/scenes/flow_stenosis_stability.toml") + " -o " +
                                  dir + "/steady.h5");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  Steady s;
  H5File f(dir + "/steady.h5", H5File::Mode::Read);
  s.u = read_state(f, "/solution/u");
  long rows = 0, cols = 0;
  const std::vector<double> spectrum = f.read_matrix("/solution/stability", &rows, &cols);  // by real part
  if (rows > 0) {
    s.sigma_re = spectrum[0];
    s.sigma_im = spectrum[1];
  }
  return s;
}

// d log(mode_amplitude) / dt by least squares over the rows with t >= t0.
double decay_rate(const TimeTable& t, double t0) {
  const int ct = t.column("t"), ca = t.column("mode_amplitude");
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (long i = 0; i < t.rows.rows(); ++i) {
    const double x = t.rows(i, ct);
    if (x < t0) continue;
    const double y = std::log(t.rows(i, ca));
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return -(n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

// runs/scenes/flow_stenosis_evolve.toml: the steady state perturbed along the least stable
// eigenvector (a complex pair, sigma = 3.1355 -+ 1.3995 i), its largest entry 1e-4 of the flow's,
// integrated by BDF2 to t = 2 at relative_tolerance 1e-6. The steady state evolve starts from is
// the one `keller solve` computes for runs/scenes/flow_stenosis_stability.toml (the same flow: to Newton's
// tolerance), and the perturbation's component along the eigenvector decays at Re sigma of solve's
// spectrum, fitted over t >= 0.5: 2.8e-4 relative (7.4e-5 at relative_tolerance 1e-7, 3.4e-5 at
// 1e-8: BDF2's error, falling as the tolerance to the power 2/3), 1e-3 allowed as in
// Dynamics.*. The next eigenvalues are 3.2408 -+ 0.5802 i and 3.5797 -+ 1.8009 i: a rate within
// 1e-3 is the least stable mode's.
TEST(FlowEvolve, APerturbationOfTheStenosisFlowDecaysAtTheLeastStableEigenvalue) {
  const std::string dir = test::scratch_dir("flow_evolve_rate");
  const Steady steady = solve_stenosis(dir);
  ASSERT_GT(steady.sigma_re, 0.0);  // stable
  auto r = test::run_keller("evolve " + test::source_path("runs/scenes/flow_stenosis_evolve.toml") + " -o " + dir +
                            "/run.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const TimeTable t = read_time_table(dir + "/run.h5");
  EXPECT_EQ(t.status, "reached t_end");
  {
    H5File f(dir + "/run.h5", H5File::Mode::Read);
    const Vector start = read_state(f, "/evolve_start/state");
    ASSERT_EQ(start.size(), steady.u.size());
    const double err = (start - steady.u).lpNorm<Eigen::Infinity>();
    EXPECT_LT(err, 1e-8 * steady.u.lpNorm<Eigen::Infinity>());
  }
  const double rate = decay_rate(t, 0.5);
  std::cout << std::setprecision(10) << "sigma = " << steady.sigma_re << " " << steady.sigma_im
            << " i; the perturbation decays at " << rate << "\n";
  EXPECT_NEAR(rate, steady.sigma_re, 1e-3 * steady.sigma_re);
}

// The same flow from a perturbation of amplitude 0.3 (its largest entry 30% of the flow's: a
// nonlinear transient) to t = 10: it returns to the steady state `keller solve` computes. The least
// stable mode alone would have decayed by exp(-3.1355 x 10) = 2.4e-14 from a deviation of 20; what
// is left is the integrator's and Newton's (steps solved to |F| ~ 1e-10): 5.6e-11 of a state of
// size 68, 1e-9 of it allowed.
TEST(FlowEvolve, ANonlinearPerturbationOfTheStenosisFlowReturnsToTheSteadyState) {
  const std::string dir = test::scratch_dir("flow_evolve_back");
  const Steady steady = solve_stenosis(dir);
  auto r = test::run_keller("evolve " + test::source_path("runs/scenes/flow_stenosis_evolve.toml") +
                            " --set evolve.amplitude=0.3 --set evolve.t_end=10 -o " + dir + "/run.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const TimeTable t = read_time_table(dir + "/run.h5");
  EXPECT_EQ(t.status, "reached t_end");
  const int dev = t.column("deviation");
  const double size = steady.u.lpNorm<Eigen::Infinity>();
  EXPECT_GT(t.rows(0, dev), 0.29 * size);  // the start: 0.3 of the state's largest entry
  const double err = (last_saved_state(dir + "/run.h5") - steady.u).lpNorm<Eigen::Infinity>();
  std::cout << "from a deviation of " << t.rows(0, dev) << " to " << err << " from solve's state\n";
  EXPECT_LT(err, 1e-9 * size);
  EXPECT_NEAR(t.rows(t.rows.rows() - 1, dev), err, 1e-10 * size);  // its own steady state is solve's
}

// A Newtonian flow at Re = 0 (Stokes flow) has no time derivative (B = 0): evolve, and solve and
// trace with [stability], refuse the scene before any work (exit 2, nothing written), naming
// parameters.Re. (Before, a spectrum was silently NaN and evolve "integrated" a steady state.)
TEST(FlowEvolve, AStokesFlowHasNoDynamicsAndIsRefusedNamingRe) {
  const std::string dir = test::scratch_dir("flow_evolve_stokes");
  const std::string steady = test::source_path("runs/scenes/flow_stenosis_stability.toml") + " --set parameters.Re=0";
  const std::string evolve = test::source_path("runs/scenes/flow_stenosis_evolve.toml") + " --set parameters.Re=0";
  for (const std::string& command : {"solve " + steady, "trace " + steady, "evolve " + evolve}) {
    SCOPED_TRACE(command);
    const auto r = test::run_keller(command + " -o " + dir + "/s.h5");
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("parameters.Re = 0"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("set parameters.Re > 0"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/s.h5"));
    EXPECT_FALSE(fs::exists(dir + "/s.h5.part"));
  }
  // the steady Stokes flow itself solves
  const auto r = test::run_keller("solve " + steady + " --set stability.enabled=false -o " + dir + "/s.h5");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// A branch in Re that starts from Stokes flow (the scene's Re = 0) has inertia: at Re = 10 it is
// the flow `keller solve` computes at Re = 10 (the pressure drop to Newton's tolerance), not the
// Stokes flow. (The convective term was assembled only where the scene's Re > 0: the branch was
// the Stokes flow at every Re, its pressure drop constant to every digit.)
TEST(FlowEvolve, ABranchInReFromStokesFlowHasInertia) {
  const std::string dir = test::scratch_dir("flow_re_from_stokes");
  const std::string scene = test::source_path("runs/scenes/flow_stenosis_stability.toml");
  auto r = test::run_keller("trace " + scene +
                            " --set parameters.Re=0 --set stability.enabled=false --set continuation.upper=10 -o " +
                            dir + "/re.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable b = read_branch_table(dir + "/re.h5");
  const long last = b.rows.rows() - 1;
  EXPECT_EQ(b.rows(0, b.column("Re")), 0.0);
  EXPECT_EQ(b.rows(last, b.column("Re")), 10.0);
  r = test::run_keller("solve " + scene + " --set stability.enabled=false -o " + dir + "/s.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  H5File f(dir + "/s.h5", H5File::Mode::Read);
  const double dp = f.read_double_attribute("/solution/observables", "dp");
  std::cout << std::setprecision(10) << "dp: Stokes " << b.rows(0, b.column("dp")) << ", the branch at Re = 10 "
            << b.rows(last, b.column("dp")) << ", solve at Re = 10 " << dp << "\n";
  EXPECT_NEAR(b.rows(last, b.column("dp")), dp, 1e-8 * std::abs(dp));
  EXPECT_GT(std::abs(dp - b.rows(0, b.column("dp"))), 1e-3 * std::abs(dp));  // inertia matters at Re = 10
}
