// The first steady state of every shipped collapsible-channel scene, on the coarse mesh of the
// regression tests, reached by continuation from the easy state the problem declares (no
// external pressure: Pe from 0, the path keller takes where Newton from the initial guess fails,
// as on M3 for the Owens fluid) is the state Newton finds from the guess on this mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "continuation/StartSolver.hpp"
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
  EXPECT_EQ(scenes, 21);  // 15 branch scenes and 6 limiting-Wi curves (docs/two_parameter.md)
}
