// keller evolve end to end: a run killed by SIGKILL leaves a readable file with every completed
// step and the same command finishes it with the uninterrupted run's result; a start from a point
// of a traced branch, perturbed along the eigenvector stored with it, grows at the stored rate;
// bad input stops with a clear message and writes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

// The Brusselator beyond its Hopf point, shortened (t_end = 10: about 1200 steps, a second).
const std::string kShort = " --set evolve.t_end=10 --set evolve.print_every=1000";

std::string evolve_scene() { return test::source_path("runs/scenes/brusselator1d_evolve.toml"); }

// d log|z| / dt with z = mode_re - i mode_im, by least squares over the rows.
double growth_rate(const TimeTable& t) {
  const int ct = t.column("t"), ca = t.column("mode_re"), cb = t.column("mode_im");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(t.rows.rows());
  for (long i = 0; i < t.rows.rows(); ++i) {
    const double x = t.rows(i, ct), y = std::log(std::hypot(t.rows(i, ca), t.rows(i, cb)));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

TEST(Evolve, AKilledRunKeepsEveryStepAndTheSameCommandFinishesIt) {
  const std::string dir = test::scratch_dir("evolve_kill");
  auto r = test::run_keller("evolve " + evolve_scene() + kShort + " -o " + dir + "/whole.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const TimeTable whole = read_time_table(dir + "/whole.h5");
  EXPECT_EQ(whole.status, "reached t_end");
  ASSERT_GT(whole.rows.rows(), 600);

  const std::string out = dir + "/run.h5", work = out + ".part";
  const std::string command = "evolve " + evolve_scene() + kShort + " -o " + out;
  r = test::run_keller(command, "KELLER_SIGNAL_AT=step:500 KELLER_SIGNAL=KILL");
  EXPECT_EQ(r.exit_code, -1) << "not killed: " << r.out;
  EXPECT_FALSE(fs::exists(out));
  ASSERT_TRUE(fs::exists(work));
  // every completed step is there, readable while the writer's flag is still set: 500 rows (steps
  // 0 to 499), equal to the uninterrupted run's to the last bit (the same computation)
  const TimeTable killed = read_time_table(work);
  EXPECT_EQ(killed.status, "running");
  ASSERT_EQ(killed.rows.rows(), 500);
  const long seconds = killed.column("seconds");
  for (long i = 0; i < killed.rows.rows(); ++i)
    for (long j = 0; j < killed.rows.cols(); ++j)
      if (j != seconds && !(std::isnan(killed.rows(i, j)) && std::isnan(whole.rows(i, j)))) {
        EXPECT_EQ(killed.rows(i, j), whole.rows(i, j)) << "row " << i << " column " << j;
      }
  const TimeSeed seed = read_time_seed(work);
  EXPECT_EQ(seed.step(), 499);
  ASSERT_EQ(seed.history.back.size(), 3u);

  // the same command continues from step 499 and ends where the uninterrupted run ended: the same
  // rows up to there, then the same steps to Newton's tolerance (the resumed run starts on a new
  // factorisation where the other kept one: 1e-10 relative to the state)
  r = test::run_keller(command);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("continuing the unfinished run"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(work));
  const TimeTable t = read_time_table(out);
  EXPECT_EQ(t.status, "reached t_end");
  ASSERT_EQ(t.rows.rows(), whole.rows.rows());
  for (long i = 0; i < t.rows.rows(); ++i) EXPECT_EQ(t.rows(i, t.column("step")), static_cast<double>(i));
  const long last = t.rows.rows() - 1;
  EXPECT_EQ(t.rows(last, t.column("t")), 10.0);
  for (const std::string c : {"u_mean", "v_mean", "u_max", "mode_re", "mode_im"}) {
    const double want = whole.rows(last, whole.column(c));
    EXPECT_NEAR(t.rows(last, t.column(c)), want, 1e-10 * std::max(1.0, std::abs(want))) << c;
  }
}

// SIGTERM (as SIGINT) stops the run after its current step: exit 130, the file keeps every step
// with the status "interrupted at t = ...", and the same command finishes it.
TEST(Evolve, AStoppedRunSaysSoAndTheSameCommandFinishesIt) {
  const std::string dir = test::scratch_dir("evolve_term");
  const std::string out = dir + "/run.h5", command = "evolve " + evolve_scene() + kShort + " -o " + out;
  auto r = test::run_keller(command, "KELLER_SIGNAL_AT=step:300 KELLER_SIGNAL=TERM");
  EXPECT_EQ(r.exit_code, 130) << r.err << r.out;
  const TimeTable stopped = read_time_table(out + ".part");
  EXPECT_EQ(stopped.status.rfind("interrupted at t = ", 0), 0u) << stopped.status;
  EXPECT_GE(stopped.rows.rows(), 300);
  r = test::run_keller(command);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_EQ(read_time_table(out).status, "reached t_end");
}

// A branch traced with [stability] stores the critical eigenvector with its stops: evolve from the
// stop at b = 5.5, perturbed along it, grows at -Re sigma of the stored eigenvalue (BDF2's error
// at the scene's tolerance: within 1e-3 relative, as in DynamicsTest).
TEST(Evolve, FromAStoredBranchPointAlongItsStoredEigenvector) {
  const std::string dir = test::scratch_dir("evolve_stored");
  auto r = test::run_keller("trace " + test::source_path("runs/scenes/brusselator1d_hopf.toml") +
                            " --set brusselator.intervals=16 -o " + dir + "/branch.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable branch = read_branch_table(dir + "/branch.h5");
  int row = -1;
  for (long i = 0; i < branch.rows.rows(); ++i)
    if (branch.rows(i, branch.column("kind")) == 2.0 && branch.rows(i, branch.column("b")) == 5.5)
      row = static_cast<int>(i);
  ASSERT_GE(row, 0);
  const auto mode = read_branch_mode(dir + "/branch.h5", row);
  ASSERT_TRUE(mode.has_value());
  ASSERT_LT(mode->sigma_re, 0.0);  // beyond the Hopf point
  r = test::run_keller("evolve " + evolve_scene() + kShort + " --set evolve.perturbation=\\\"stored\\\" --restart " +
                       dir + "/branch.h5:" + std::to_string(row) + " -o " + dir + "/run.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("starting from row"), std::string::npos) << r.out;
  const TimeTable t = read_time_table(dir + "/run.h5");
  EXPECT_NEAR(growth_rate(t), -mode->sigma_re, 1e-3 * std::abs(mode->sigma_re));
  H5File f(dir + "/run.h5", H5File::Mode::Read);
  EXPECT_EQ(f.read_double_attribute("/problem/parameters", "b"), 5.5);  // the stored point's parameters
}

TEST(Evolve, BadInputIsRefusedWithItsKeyAndNothingIsWritten) {
  const std::string dir = test::scratch_dir("evolve_bad");
  const std::string out = dir + "/run.h5";
  struct Case {
    std::string args, says;
  };
  const std::vector<Case> cases = {
      {"--set evolve.t_end=-1", "evolve.t_end"},
      {"--set evolve.stepsize=1", "evolve.stepsize"},
      {"--set evolve.perturbation=\\\"stored\\\"", "evolve.perturbation"},
      {"--set evolve.fixed_step=true", "evolve.initial_step"},
      {"--set evolve.relative_tolerance=2", "evolve.relative_tolerance"},
      {"--restart " + dir + "/missing.h5:0", "missing.h5"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.args);
    const auto r = test::run_keller("evolve " + evolve_scene() + " " + c.args + " -o " + out);
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out + ".part"));
  }
}

// The collapsible-channel scene in coarse mode (the hard cases' mesh) through the driver: the
// perturbation along the least stable eigenvector of the moving-wall form decays at -Re sigma
// (1e-3 relative at 1e-7 of the deviation per step, as DynamicsTest finds), the fields of the
// stored states come with an XDMF file, the time table exports as CSV and the figure script draws it.
TEST(Evolve, TheCollapsibleSceneDecaysAtItsEigenvalueAndExports) {
  const std::string dir = test::scratch_dir("evolve_collapsible");
  const std::string out = dir + "/run.h5";
  const std::string coarse =
      " --set mesh.name=\\\"custom\\\" --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set mesh.nx_downstream=5"
      " --set mesh.ny_fluid=4 --set mesh.ny_solid=2";
  auto r = test::run_keller("evolve " + test::source_path("runs/scenes/evolve_collapsible_newtonian.toml") + coarse +
                            " -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  const TimeTable t = read_time_table(out);
  double sigma = 0.0;
  {
    H5File f(out, H5File::Mode::Read);
    sigma = f.read_double_attribute("/evolve_start/mode", "sigma_re");
    EXPECT_TRUE(f.exists("/evolve/fields/0"));
  }
  ASSERT_GT(sigma, 0.0);
  EXPECT_NEAR(growth_rate(t), -sigma, 1e-3 * sigma);
  EXPECT_TRUE(fs::exists(dir + "/run.xdmf"));
  r = test::run_keller("export " + out + " --csv " + dir + "/run.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream csv(dir + "/run.csv");
  long lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, t.rows.rows() + 1);
  const std::string plot =
      test::python_module("keller.plot evolve") + " " + out + " --log -o " + dir + "/run.png > /dev/null";
  EXPECT_EQ(std::system(plot.c_str()), 0);
  EXPECT_TRUE(fs::exists(dir + "/run.png"));
}
