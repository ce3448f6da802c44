// The spectrum of one steady state (keller solve with [stability] enabled), the physical
// time-dependent form of the collapsible channel as what a scene gets by default, and counts of
// eigenvalues that a problem cannot give refused before any work.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

// The collapsible channel on a coarse mesh, Newtonian Stokes flow, with its spectrum.
std::string coarse_stokes_channel() {
  return test::source_path("runs/scenes/collapsible_oldroyd_b.toml") +
         " --set fluid.model='\"newtonian\"' --set mesh.name='\"custom\"' --set mesh.nx_upstream=3 --set "
         "mesh.nx_deformable=6 --set mesh.nx_downstream=3 --set mesh.ny_fluid=3 --set mesh.ny_solid=1 --set "
         "stability.enabled=true";
}

}  // namespace

// A scene that asks for stability gets the physical form: Newtonian Stokes flow in the collapsible
// channel has finite eigenvalues there (the wall relaxing through the viscous fluid: real, stable,
// slow), stored in /solution/stability with residuals below the tolerance. The fixed-wall form,
// asked for, has none (B = 0 without inertia or polymer).
TEST(SolveStability, TheSpectrumOfTheStateIsComputedPrintedAndStored) {
  const std::string dir = test::scratch_dir("solve_stability");
  const auto r = test::run_keller("solve " + coarse_stokes_channel() + " -o " + dir + "/s.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("stability: 0 unstable of the 6 eigenvalues"), std::string::npos) << r.out;
  H5File f(dir + "/s.h5", H5File::Mode::Read);
  long rows = 0, cols = 0;
  const std::vector<double> sigma = f.read_matrix("/solution/stability", &rows, &cols);
  ASSERT_EQ(rows, 6);
  ASSERT_EQ(cols, 3);
  EXPECT_EQ(f.read_double_attribute("/solution/stability", "unstable"), 0.0);
  for (long i = 0; i < rows; ++i) {
    EXPECT_GT(sigma[static_cast<size_t>(3 * i)], 0.0);            // stable
    EXPECT_LT(sigma[static_cast<size_t>(3 * i + 2)], 1e-8) << i;  // residual below the default tolerance
  }
  // the least stable mode is the wall's, real and slow (units G / eta0: the flow's own are > 1e-3)
  EXPECT_EQ(sigma[1], 0.0);
  EXPECT_LT(sigma[0], 1e-3);

  const auto fixed = test::run_keller("solve " + coarse_stokes_channel() +
                                      " --set dynamics.mass_matrix='\"fixed-wall\"' -o " + dir + "/fixed.h5");
  ASSERT_EQ(fixed.exit_code, 0) << fixed.err;
  EXPECT_NE(fixed.out.find("stability: no finite eigenvalue"), std::string::npos) << fixed.out;
  H5File g(dir + "/fixed.h5", H5File::Mode::Read);
  g.read_matrix("/solution/stability", &rows, &cols);
  EXPECT_EQ(rows, 0);
}

// More eigenvalues than the problem has unknowns (less two, ARPACK's bound) are refused naming the
// key, before any work and without an output, by solve and trace alike; a count beyond any problem
// (2^31 - 1, which built a column name per eigenvalue until memory ran out) by the key's range.
TEST(SolveStability, ACountBeyondTheProblemSizeIsRefusedNamingTheKey) {
  const std::string dir = test::scratch_dir("solve_stability_count");
  for (const std::string command : {"solve", "trace"})
    for (const std::string count : {"17", "2147483647"}) {
      SCOPED_TRACE(command + " count " + count);
      const auto r =
          test::run_keller(command + " " + test::source_path("runs/scenes/brusselator1d_hopf.toml") +
                           " --set brusselator.intervals=8 --set stability.count=" + count + " -o " + dir + "/c.h5");
      EXPECT_EQ(r.exit_code, 2);
      EXPECT_NE(r.err.find("'stability.count'"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find(count == "17" ? "18 unknowns has at most 16" : "out of range"), std::string::npos) << r.err;
      EXPECT_FALSE(fs::exists(dir + "/c.h5"));
      EXPECT_FALSE(fs::exists(dir + "/c.h5.part"));
    }
}

// A problem that the scene gives no time-dependent form (the wall without inertia: every row is
// quasi-static) has no spectrum and nothing to integrate in time: solve and trace with [stability]
// and evolve refuse the scene before any work, without an output (it was "internal error", exit 4,
// and trace left OUT.h5.part behind).
TEST(SolveStability, AProblemWithoutATimeFormIsRefusedForItsSpectrumAndItsDynamics) {
  const std::string dir = test::scratch_dir("solve_stability_no_time_form");
  const std::string wall = test::source_path("runs/scenes/wall_pressure.toml");
  // evolve's scene: the shipped one up to its [continuation] section, which evolve does not read
  const std::string evolve_scene = dir + "/wall_evolve.toml";
  {
    std::ifstream in(wall);
    std::ofstream out(evolve_scene);
    for (std::string line; std::getline(in, line) && line != "[continuation]";) out << line << '\n';
  }
  for (const std::string command : {"solve", "trace", "evolve"}) {
    SCOPED_TRACE(command);
    const std::string scene = command == "evolve" ? evolve_scene : wall + " --set stability.enabled=true";
    const auto r = test::run_keller(command + " " + scene + " -o " + dir + "/w.h5");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("problem 'wall' has no time-dependent form"), std::string::npos) << r.err;
    if (command != "evolve") {
      EXPECT_NE(r.err.find("'stability.enabled'"), std::string::npos) << r.err;
    }
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/w.h5"));
    EXPECT_FALSE(fs::exists(dir + "/w.h5.part"));
  }
}
