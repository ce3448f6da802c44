// The `flow` problem from a scene: a mesh from a Gmsh file, conditions on its named boundaries,
// observables; Poiseuille flow from a .msh is exact to rounding; every mismatch between the mesh's
// boundaries and the scene's conditions, and every incomplete condition or observable, is an error
// naming what to change.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/BlockMeshBuilder.hpp"
#include "core/GmshMesh.hpp"
#include "core/Newton.hpp"
#include "problems/flow/FlowProblem.hpp"
#include "runs/SceneLoader.hpp"

using namespace keller;

namespace {

namespace fs = std::filesystem;

// A straight channel [0, L] x [0, H] of nx x ny elements, boundaries inflow (x = 0), outflow
// (x = L), bottom (y = 0), top (y = H).
Mesh channel_mesh(double L, double H, int nx, int ny) {
  BlockMeshBuilder b;
  b.add_block({"channel",
               "fluid",
               nx,
               ny,
               Grading::uniform(),
               Grading::uniform(),
               [=](double s, double t) {
                 return Mesh::Point{L * s, H * t};
               },
               {"bottom", "outflow", "top", "inflow"}});
  return b.build();
}

struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() / ("keller_flow_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

const char* kConditions =
    "[boundaries.inflow]\ntype = \"inflow\"\n[boundaries.outflow]\ntype = \"outflow\"\n"
    "[boundaries.bottom]\ntype = \"wall\"\n[boundaries.top]\ntype = \"wall\"\n";

LoadedScene scene_in(const Scratch& s, const std::string& body) {
  return load_scene(s.write("flow.toml", "[problem]\ntype = \"flow\"\n" + body));
}

std::string error_of(const Scratch& s, const std::string& body) {
  try {
    const LoadedScene l = scene_in(s, body);
    build_problem(l, "flow.toml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// Q2 velocity holds the parabola and P1disc the linear pressure: the Stokes solution on a straight
// mesh read from a .msh is the exact one to rounding (u = 6 U y (H - y) / H^2, dP/dx = -12 U / H^2).
TEST(FlowProblem, PoiseuilleFromAMshFileIsExact) {
  Scratch s;
  write_gmsh_mesh(channel_mesh(6.0, 2.0, 6, 4), (s.dir / "channel.msh").string());
  const LoadedScene l = scene_in(s, std::string("[mesh]\nfile = \"channel.msh\"\n") + kConditions +
                                        "[observables.Q]\ntype = \"flow-rate\"\nboundary = \"outflow\"\n"
                                        "[observables.dp]\ntype = \"pressure-drop\"\nboundary = \"inflow\"\nto = "
                                        "\"outflow\"\n[observables.F]\ntype = \"force\"\nboundary = \"top\"\n");
  auto problem = build_problem(l, "flow.toml");
  Vector u = problem->initial_guess();
  ASSERT_TRUE(NewtonSolver(*problem).solve(u).converged());
  auto& flow = dynamic_cast<FlowProblem&>(*problem);
  const int fv = flow.dofs().field_index("velocity");
  double err = 0;
  for (int n = 0; n < flow.mesh().num_nodes(); ++n) {
    const double y = flow.mesh().node(n)[1];
    err = std::max(err, std::abs(u[flow.dofs().node_dof(fv, n, 0)] - 6.0 * y * (2.0 - y) / 4.0));
    err = std::max(err, std::abs(u[flow.dofs().node_dof(fv, n, 1)]));
  }
  EXPECT_LT(err, 1e-12);
  std::vector<double> v;
  ASSERT_TRUE(problem->observables(u, v).is_ok());
  ASSERT_EQ(problem->observable_names(), (std::vector<std::string>{"F", "Q", "dp"}));
  // the wall shear stress is 6 U / H at each wall: the force on the top wall is 6 U L / H along x
  EXPECT_NEAR(v[0], 6.0 * 6.0 / 2.0, 1e-10);
  EXPECT_NEAR(v[1], 2.0, 1e-12);               // U H
  EXPECT_NEAR(v[2], 12.0 / 4.0 * 6.0, 1e-10);  // -dP/dx L
}

TEST(FlowProblem, TheMeshsBoundariesAndTheScenesConditionsMustMatch) {
  Scratch s;
  write_gmsh_mesh(channel_mesh(2.0, 1.0, 2, 2), (s.dir / "channel.msh").string());
  const std::string mesh = "[mesh]\nfile = \"channel.msh\"\n";
  const std::string missing = error_of(s, mesh +
                                              "[boundaries.inflow]\ntype = \"inflow\"\n[boundaries.outflow]\ntype = "
                                              "\"outflow\"\n[boundaries.bottom]\ntype = \"wall\"\n");
  EXPECT_NE(missing.find("boundary top has no condition in the scene"), std::string::npos) << missing;
  EXPECT_NE(missing.find("the scene names: bottom, inflow, outflow"), std::string::npos) << missing;
  const std::string extra = error_of(s, mesh + kConditions + "[boundaries.lid]\ntype = \"wall\"\n");
  EXPECT_NE(extra.find("the scene gives a condition on lid, which the mesh does not have"), std::string::npos) << extra;
  EXPECT_NE(extra.find("has: bottom, inflow, outflow, top"), std::string::npos) << extra;
  const std::string region =
      error_of(s, "[mesh]\nfile = \"channel.msh\"\nregion = \"solid\"\n" + std::string(kConditions));
  EXPECT_NE(region.find("mesh.region = \"solid\": the mesh"), std::string::npos) << region;
  EXPECT_NE(region.find("has no such region (it has: fluid)"), std::string::npos) << region;
}

TEST(FlowProblem, IncompleteConditionsAndObservablesNameTheirKey) {
  Scratch s;
  write_gmsh_mesh(channel_mesh(2.0, 1.0, 2, 2), (s.dir / "channel.msh").string());
  const std::string mesh = "[mesh]\nfile = \"channel.msh\"\n";
  auto expect = [&](const std::string& body, const std::string& what) {
    const std::string e = error_of(s, body);
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  expect(kConditions, "a flow needs exactly one of mesh.file (a .msh) and mesh.geo");
  expect(mesh + "geo = \"x.geo\"\n" + kConditions, "a flow needs exactly one of");
  expect(mesh + "[boundaries.top]\n", "key 'boundaries.top.type' (default): every boundary needs a type");
  expect(mesh + "[boundaries.top]\ntype = \"moving-wall\"\n",
         "key 'boundaries.top.velocity' (default): a moving wall needs two numbers");
  expect(mesh + "[boundaries.top]\ntype = \"wall\"\nvelocity = [1, 0]\n",
         "key 'boundaries.top.velocity': does not apply to a boundary of type \"wall\"");
  expect(mesh + "[boundaries.top]\ntype = \"traction\"\ntraction = [1]\n",
         "a traction needs two numbers [x, y], got 1");
  expect(mesh + kConditions + "[observables.F]\ntype = \"force\"\n",
         "key 'observables.F.boundary' (default): an observable of type \"force\" needs it");
  expect(mesh + kConditions + "[observables.F]\ntype = \"force\"\nboundary = \"lid\"\n", "F");
  expect(mesh + kConditions + "[observables.X]\ntype = \"reattachment\"\nboundary = \"top\"\n",
         "key 'observables.X.origin' (default): a reattachment length's origin needs two numbers");
  expect(
      mesh + kConditions + "[observables.P]\ntype = \"stream-function\"\nboundary = \"top\"\nregion = [1, 0, 0, 1]\n",
      "needs a box [xmin, xmax, ymin, ymax] with xmin < xmax");
  expect(std::string("[mesh]\nfile = \"absent.msh\"\n") + kConditions, "absent.msh");
  // a name that is already a column of the table (a parameter, the fluid's min m1, the stepper's)
  // would make the branch table hold one name twice: refused, naming the observable
  for (const char* taken : {"Re", "Wi", "min_m1", "seconds", "s"})
    expect(mesh + kConditions + "[observables." + taken + "]\ntype = \"flow-rate\"\nboundary = \"inflow\"\n",
           std::string("key 'observables.") + taken + ".type': the name \"" + taken + "\" is taken");
  expect(mesh + kConditions + "[observables.Q-in]\ntype = \"flow-rate\"\nboundary = \"inflow\"\n",
         "is a column name: letters, digits and _ only");
  EXPECT_EQ(error_of(s, mesh + kConditions + "[observables.Q_in2]\ntype = \"flow-rate\"\nboundary = \"inflow\"\n"), "");
}
