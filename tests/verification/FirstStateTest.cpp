// The first steady state of every shipped collapsible-channel scene, on the coarse mesh of the
// regression tests, reached by continuation from the easy state the problem declares (no
// external pressure: Pe from 0, the path keller takes where Newton from the initial guess fails,
// as on M3 for the Owens fluid) is the state Newton finds from the guess on this mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "continuation/output/BranchFile.hpp"
#include "continuation/start/StartSolver.hpp"
#include "core/H5File.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

TEST(FirstState, EveryCollapsibleSceneIsReachedFromItsEasyState) {
  const std::vector<std::string> coarse = {"mesh.name=\"custom\"", "mesh.nx_upstream=5", "mesh.nx_deformable=10",
                                           "mesh.nx_downstream=5", "mesh.ny_fluid=4",    "mesh.ny_solid=2"};
  int scenes = 0;
  for (const auto& entry : fs::directory_iterator(test::source_path("runs/scenes"))) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("collapsible_", 0) != 0) continue;
    SCOPED_TRACE(name);
    ++scenes;
    const LoadedScene loaded = load_scene(entry.path().string(), declare_trace_keys, coarse);
    auto problem = loaded.type->build(loaded.scene);
    const NewtonOptions nopt = newton_options_from(loaded.scene);
    const SparseLUOptions lopt = sparse_lu_options_from(loaded.scene);
    Vector reference = problem->initial_guess();
    ASSERT_TRUE(NewtonSolver(*problem, nopt, lopt).solve(reference).converged());
    std::vector<double> want, got;
    ASSERT_TRUE(problem->observables(reference, want).is_ok());

    StartOptions by_parameters;
    by_parameters.path = StartOptions::Path::Parameters;
    StartSolver start(*problem, nopt, lopt, by_parameters);
    Vector u = problem->initial_guess();
    const StartResult r = start.solve(u);
    ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
    EXPECT_TRUE(r.by_continuation);
    EXPECT_NE(r.path.find("Pe from 0 to 0.04"), std::string::npos) << r.path;
    ASSERT_TRUE(problem->observables(u, got).is_ok());
    const auto names = problem->observable_names();
    double worst = 0;
    for (size_t k = 0; k < names.size(); ++k) {
      if (names[k] == "area_change" || names[k] == "Q_in" || names[k] == "Q_out") continue;  // rounding-level or fixed
      // both states solve F to 1e-10 times its scale; an observable moves by its condition
      // number times that: 1e-8 relative (to 1 or the value) leaves a condition number of 1e2
      // (they agree to 5e-12 or better)
      const double d = std::abs(got[k] - want[k]) / std::max(1.0, std::abs(want[k]));
      worst = std::max(worst, d);
      EXPECT_LT(d, 1e-8) << names[k] << ": " << got[k] << " against " << want[k];
    }
    std::cout << name << ": " << r.path << ", " << r.steps << " points, " << r.factorisations
              << " factorisations; observables agree to " << worst << "\n";
  }
  // 18 branch scenes (one of a two-mode fluid) and 7 limiting-Wi curves (docs/two_parameter.md, docs/fluids.md)
  EXPECT_EQ(scenes, 25);
}

// The thinnest wall of the range with the Owens fluid (t = 0.1, Gamma = 4.95e-4): Newton fails
// from the guess, and at no load (Pe = 0) and at the smallest Gamma the flow's own load still
// deforms the thin wall too far; the start solves the reference thickness t = 0.4 there and thins
// the wall. The state it reaches is the end of the scene's own thickness branch (t from 0.4 to 0.1
// at the scene's load, landed exactly on the bound): two paths through different parameters to
// one state, whose observables agree to 1e-8 as above.
TEST(FirstState, TheThinnestOwensWallIsReachedFromTheReferenceThickness) {
  const std::string coarse =
      " --set mesh.name=custom --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set mesh.nx_downstream=5"
      " --set mesh.ny_fluid=4 --set mesh.ny_solid=2 --set output.xdmf=false";
  const std::string dir = test::scratch_dir("first_state_thin_owens");
  const std::string scene = test::source_path("runs/scenes/collapsible_owens_thickness.toml");
  auto branch = test::run_keller("trace " + scene + coarse + " -o " + dir + "/branch.h5");
  ASSERT_EQ(branch.exit_code, 0) << branch.out << branch.err;
  auto solved = test::run_keller("solve " + scene + coarse + " --set parameters.t=0.1 -o " + dir + "/thin.h5");
  ASSERT_EQ(solved.exit_code, 0) << solved.out << solved.err;
  EXPECT_NE(solved.out.find("t from 0.4 to 0.1"), std::string::npos) << solved.out;
  const BranchTable b = read_branch_table(dir + "/branch.h5");
  ASSERT_GT(b.rows.rows(), 1);
  const auto at_end = [&](const std::string& name) { return b.rows(b.rows.rows() - 1, b.column(name)); };
  H5File s(dir + "/thin.h5", H5File::Mode::Read);
  EXPECT_DOUBLE_EQ(at_end("t"), 0.1);
  for (const char* name : {"dy_max", "dx_max", "gap_min", "dP", "min_m1", "max_m3"}) {
    const double want = at_end(name), got = s.read_double_attribute("/solution/observables", name);
    EXPECT_LT(std::abs(got - want) / std::max(1.0, std::abs(want)), 1e-8) << name << ": " << got << " against " << want;
  }
}
