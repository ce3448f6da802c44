// The confined cylinder posed as a `flow` (a Gmsh mesh, conditions by boundary name, the drag as
// a declared force observable) gives the built-in `cylinder` problem's drag: on the built-in mesh
// itself, written as a .msh and read back, to rounding (the same discrete problem); on the mesh
// runs/geometries/cylinder.geo makes (C1 with f = 1: every node within 1e-7 of the built-in mesh's,
// docs/geometries.md) to 1e-6 relative, the agreement the issue asks for. Oldroyd-B, beta = 0.59,
// log-conformation, Wi from 0.01 to 0.5 by natural continuation (Newton from the last state).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/GmshMesh.hpp"
#include "core/Newton.hpp"
#include "problems/cylinder/CylinderProblem.hpp"
#include "problems/flow/FlowProblem.hpp"
#include "runs/SceneLoader.hpp"

using namespace keller;

namespace {

const std::vector<double> kWi = {0.01, 0.1, 0.2, 0.3, 0.4, 0.5};

FluidOptions oldroyd_b_log() {
  FluidOptions f;
  f.model = FluidModel::OldroydB;
  f.log_conformation = true;
  f.beta = 0.59;
  f.Wi = kWi.front();
  return f;
}

// The drag along the Wi steps, each state from the last. `drag` reads K from the state.
template <class Drag>
std::vector<double> drags(Problem& p, const Drag& drag) {
  std::vector<double> out;
  Vector u = p.initial_guess();
  const int iWi = p.parameters().index("Wi");
  for (double wi : kWi) {
    p.parameters().set(iWi, wi);
    if (!NewtonSolver(p).solve(u).converged()) return out;
    out.push_back(drag(u));
  }
  return out;
}

std::vector<double> builtin_drags() {
  CylinderOptions o;
  o.mesh = CylinderMeshSpec::preset("C1");
  o.fluid = oldroyd_b_log();
  CylinderProblem p(o);
  return drags(p, [&](const Vector& u) { return p.drag(u); });
}

std::vector<double> flow_drags(const std::string& mesh_keys) {
  const std::string scene =
      "[problem]\ntype = \"flow\"\n" + mesh_keys +
      "[fluid]\nmodel = \"oldroyd-b\"\nformulation = \"log-conformation\"\n[parameters]\nbeta = 0.59\nWi = 0.01\n"
      "[boundaries.inflow]\ntype = \"inflow\"\n[boundaries.outflow]\ntype = \"outflow\"\n"
      "[boundaries.wall]\ntype = \"wall\"\n[boundaries.symmetry]\ntype = \"symmetry\"\n"
      "[boundaries.cylinder]\ntype = \"wall\"\n"
      "[observables.K]\ntype = \"force\"\nboundary = \"cylinder\"\ncomponent = \"x\"\nscale = 2.0\n";
  const LoadedScene l = load_scene_text(scene, "flow_cylinder.toml");
  auto p = build_problem(l, "flow_cylinder.toml");
  EXPECT_EQ(p->observable_names().front(), "K");
  return drags(*p, [&](const Vector& u) {
    std::vector<double> v;
    return p->observables(u, v).is_ok() ? v.front() : NAN;
  });
}

}  // namespace

TEST(FlowCylinder, TheBuiltInMeshAsAMshGivesTheBuiltInDragToRounding) {
  const std::string msh = ::testing::TempDir() + "keller_flow_cylinder_c1.msh";
  CylinderOptions o;
  o.mesh = CylinderMeshSpec::preset("C1");
  write_gmsh_mesh(build_cylinder_mesh(o), msh);
  const std::vector<double> builtin = builtin_drags(), flow = flow_drags("[mesh]\nfile = \"" + msh + "\"\n");
  std::filesystem::remove(msh);
  ASSERT_EQ(builtin.size(), kWi.size());
  ASSERT_EQ(flow.size(), kWi.size());
  for (size_t k = 0; k < kWi.size(); ++k) EXPECT_NEAR(flow[k], builtin[k], 1e-10 * builtin[k]) << "Wi " << kWi[k];
  // and the drag is the benchmark's: 132.36 at Wi = 0 within C1's 0.02% (docs/cylinder.md)
  EXPECT_NEAR(builtin.front(), 132.36, 0.03);
}

TEST(FlowCylinder, TheGeoMeshGivesTheBuiltInDragTo1e6) {
  const std::vector<double> builtin = builtin_drags();
  const std::vector<double> flow = flow_drags("[mesh]\ngeo = \"" + std::string(KELLER_SOURCE_DIR) +
                                              "/runs/geometries/cylinder.geo\"\n[mesh.geo_parameters]\nf = 1\n");
  ASSERT_EQ(flow.size(), kWi.size());
  for (size_t k = 0; k < kWi.size(); ++k) EXPECT_NEAR(flow[k], builtin[k], 1e-6 * builtin[k]) << "Wi " << kWi[k];
}
