// The `flow` problem from a scene: a mesh from a Gmsh file, conditions on its named boundaries,
// observables; Poiseuille flow from a .msh is exact to rounding; every mismatch between the mesh's
// boundaries and the scene's conditions, and every incomplete condition or observable, is an error
// naming what to change.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

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

// min_m1 of a viscoelastic flow is a minimum over places, the conformation's nodes (what an event
// curve follows): their minimum is the monitor, the gradient of m1 at a place (central differences
// in that node's own unknowns) agrees with central differences of that place's value in every
// unknown, and the observable min_m1 has the monitor's gradient; an observable of the scene has
// none. Oldroyd-B Poiseuille flow at Wi = 0.7 (m1 falls towards the walls), in both forms.
TEST(FlowProblem, MinM1HasPlacesAndGradients) {
  Scratch s;
  write_gmsh_mesh(channel_mesh(2.0, 1.0, 2, 3), (s.dir / "channel.msh").string());
  for (const char* form : {"conformation", "log-conformation"}) {
    SCOPED_TRACE(form);
    const LoadedScene l =
        scene_in(s, std::string("[mesh]\nfile = \"channel.msh\"\n[fluid]\nmodel = \"oldroyd-b\"\n") +
                        "formulation = \"" + form + "\"\n[parameters]\nWi = 0.7\nbeta = 0.3\n" + kConditions +
                        "[observables.Q]\ntype = \"flow-rate\"\nboundary = \"outflow\"\n");
    auto problem = build_problem(l, "flow.toml");
    Vector u = problem->initial_guess();
    ASSERT_TRUE(NewtonSolver(*problem).solve(u).converged());
    auto& flow = dynamic_cast<FlowProblem&>(*problem);
    ASSERT_TRUE(flow.has_places(0));
    EXPECT_FALSE(flow.has_places(1));
    std::vector<double> places, monitors;
    ASSERT_TRUE(flow.monitor_places(0, u, places).is_ok());
    ASSERT_TRUE(flow.monitors(u, monitors).is_ok());
    ASSERT_EQ(places.size(), 3u * 4u);  // the vertices of 2 x 3 elements
    const auto lowest = std::min_element(places.begin(), places.end());
    EXPECT_EQ(*lowest, monitors[0]);
    EXPECT_LT(*lowest, 0.9);  // sheared: well below the relaxed 1
    for (int place : {static_cast<int>(lowest - places.begin()), 0, 10}) {
      Vector g;
      ASSERT_TRUE(flow.monitor_place_gradient(0, place, u, g).is_ok());
      ASSERT_EQ(g.size(), u.size());
      Vector w = u;
      double largest = 0, err = 0;
      for (int d = 0; d < u.size(); ++d) {
        const double h = 1e-6 * std::max(1.0, std::abs(u[d]));
        std::vector<double> hi, lo;
        w[d] = u[d] + h;
        flow.monitor_places(0, w, hi);
        w[d] = u[d] - h;
        flow.monitor_places(0, w, lo);
        w[d] = u[d];
        const double fd = (hi[static_cast<size_t>(place)] - lo[static_cast<size_t>(place)]) / (2 * h);
        largest = std::max(largest, std::abs(fd));
        err = std::max(err, std::abs(fd - g[d]));
      }
      EXPECT_GT(largest, 0.1) << "place " << place;
      // the same differences, in the same unknowns (zero elsewhere): equal to rounding
      EXPECT_LT(err, 1e-12 * std::max(largest, 1.0) + 1e-9) << "place " << place;
    }
    const int min_m1 = static_cast<int>(problem->observable_names().size()) - 4;  // min_m1, _x, _y, max_m3
    ASSERT_EQ(problem->observable_names()[static_cast<size_t>(min_m1)], "min_m1");
    EXPECT_TRUE(flow.has_observable_gradient(min_m1));
    EXPECT_FALSE(flow.has_observable_gradient(0));  // Q
    Vector go, gm;
    ASSERT_TRUE(flow.observable_gradient(min_m1, u, go).is_ok());
    ASSERT_TRUE(flow.monitor_gradient(0, u, gm).is_ok());
    EXPECT_EQ((go - gm).lpNorm<Eigen::Infinity>(), 0.0);
  }
}

// What B of B du/dt = -F a flow has: Newtonian, Re times the velocity's (consistent) mass matrix,
// nothing in the pressure; at Re = 0 nothing at all, and the problem says why, naming
// parameters.Re (evolve and a spectrum refuse it: FlowDynamicsTest). Oldroyd-B at Re = 0: the
// conformation's rows and columns only (the velocity has no time derivative in creeping flow).
TEST(FlowProblem, TheMassMatrixIsReTimesTheVelocitysAndEmptyInStokesFlow) {
  Scratch s;
  write_gmsh_mesh(channel_mesh(2.0, 1.0, 2, 2), (s.dir / "channel.msh").string());
  auto built = [&](const std::string& fluid) {
    return build_problem(scene_in(s, "[mesh]\nfile = \"channel.msh\"\n" + fluid + kConditions), "flow.toml");
  };
  // the fields whose columns of B are nonzero
  auto columns_of = [](FlowProblem& p, const SparseMatrix& B) {
    std::set<std::string> fields;
    std::vector<int> field_of(static_cast<size_t>(p.size()), -1);
    for (int f = 0; f < p.dofs().num_fields(); ++f)
      for (int n = 0; n < p.mesh().num_nodes(); ++n)
        for (int c = 0; c < p.dofs().num_components(f); ++c)
          if (const int d = p.dofs().node_dof(f, n, c); d >= 0) field_of[static_cast<size_t>(d)] = f;
    for (int k = 0; k < B.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(B, k); it; ++it)
        if (it.value() != 0.0) {
          const int f = field_of[static_cast<size_t>(it.col())];
          fields.insert(f < 0 ? "pressure" : p.dofs().field(f).name);  // P1disc: element unknowns
        }
    return fields;
  };
  {
    auto problem = built("[parameters]\nRe = 1.0\n");
    auto& flow = dynamic_cast<FlowProblem&>(*problem);
    Vector u = problem->initial_guess();
    SparseMatrix B1, B;
    ASSERT_TRUE(problem->mass_matrix(u, B1).is_ok());
    EXPECT_EQ(columns_of(flow, B1), std::set<std::string>{"velocity"});
    EXPECT_TRUE(problem->why_no_time_derivative().empty());
    problem->parameters().set("Re", 2.5);
    ASSERT_TRUE(problem->mass_matrix(u, B).is_ok());
    EXPECT_LT(SparseMatrix(B - 2.5 * B1).coeffs().cwiseAbs().maxCoeff(), 1e-15 * B.coeffs().cwiseAbs().maxCoeff());
    problem->parameters().set("Re", 0.0);
    ASSERT_TRUE(problem->mass_matrix(u, B).is_ok());
    EXPECT_EQ(B.coeffs().cwiseAbs().maxCoeff(), 0.0);
    EXPECT_NE(problem->why_no_time_derivative().find("parameters.Re = 0"), std::string::npos);
    EXPECT_EQ(time_form_refusal(*problem), problem->why_no_time_derivative());
  }
  {
    auto problem = built("[fluid]\nmodel = \"oldroyd-b\"\n[parameters]\nWi = 0.5\n");
    auto& flow = dynamic_cast<FlowProblem&>(*problem);
    Vector u = problem->initial_guess();
    SparseMatrix B;
    ASSERT_TRUE(problem->mass_matrix(u, B).is_ok());
    EXPECT_EQ(columns_of(flow, B), std::set<std::string>{"conformation"});
    EXPECT_TRUE(time_form_refusal(*problem).empty());
  }
}
