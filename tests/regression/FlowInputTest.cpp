// A flow's own inputs through the real driver, and the capabilities every problem has on it
// (a branch in Re with its spectra, a restart from a labelled point, export for ParaView): a mesh keller cannot use
// (triangles, a damaged .msh, a .geo with an error or an undeclared parameter) and boundary conditions that do not
// match the mesh are refused before any work, exit code 2, with a message naming the file and
// what to change, and nothing is written; the shipped Newtonian contraction solves and stores
// the mesh the .geo made.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

const char* kSquareGeo = R"(DefineConstant[ L = {1, Name "L"} ];
Point(1) = {0, 0, 0}; Point(2) = {L, 0, 0}; Point(3) = {L, 1, 0}; Point(4) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 3; Transfinite Surface{1};
Physical Surface("fluid") = {1};
Physical Curve("bottom") = {1}; Physical Curve("outflow") = {2}; Physical Curve("top") = {3}; Physical Curve("inflow") = {4};
)";

const char* kConditions =
    "[boundaries.inflow]\ntype = \"inflow\"\n[boundaries.outflow]\ntype = \"outflow\"\n"
    "[boundaries.bottom]\ntype = \"wall\"\n[boundaries.top]\ntype = \"wall\"\n";

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

}  // namespace

TEST(FlowInput, UnusableMeshesAndMismatchedConditionsAreRefusedBeforeAnyWork) {
  const std::string dir = test::scratch_dir("flow_input");
  const std::string good = std::string(kSquareGeo) + "Recombine Surface{1};\nMesh.ElementOrder = 2;\n";
  write(dir + "/square.geo", good);
  write(dir + "/triangles.geo", std::string(kSquareGeo) + "Mesh.ElementOrder = 2;\n");
  write(dir + "/broken.geo", good + "Line(9) = {1, 77};\n");
  write(dir + "/damaged.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 9 1 9\n2 1 0 9\n");
  struct Case {
    std::string scene, expected;
  };
  const std::vector<Case> cases = {
      {"[mesh]\ngeo = \"triangles.geo\"\n" + std::string(kConditions), "triangles.geo"},
      {"[mesh]\ngeo = \"triangles.geo\"\n" + std::string(kConditions), "Recombine"},
      {"[mesh]\ngeo = \"broken.geo\"\n" + std::string(kConditions), "broken.geo"},
      {"[mesh]\nfile = \"damaged.msh\"\n" + std::string(kConditions), "damaged.msh"},
      {"[mesh]\ngeo = \"square.geo\"\n[mesh.geo_parameters]\nH = 2.0\n" + std::string(kConditions), "H"},
      {"[mesh]\ngeo = \"square.geo\"\n[boundaries.inflow]\ntype = \"inflow\"\n",
       "boundaries bottom, outflow, top have no condition in the scene"},
      {"[mesh]\ngeo = \"square.geo\"\n" + std::string(kConditions) + "[boundaries.lid]\ntype = \"wall\"\n",
       "the scene gives a condition on lid, which the mesh does not have"},
  };
  for (size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE(cases[k].scene);
    const std::string scene = dir + "/s" + std::to_string(k) + ".toml", out = dir + "/out" + std::to_string(k) + ".h5";
    write(scene, "[problem]\ntype = \"flow\"\n" + cases[k].scene);
    const auto r = test::run_keller("solve " + scene + " -o " + out);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(cases[k].expected), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(scene), std::string::npos) << r.err;  // the scene is named too
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out + ".part"));
  }
  // the good mesh with the same conditions solves, and the file holds the mesh the .geo made
  write(dir + "/ok.toml", "[problem]\ntype = \"flow\"\n[mesh]\ngeo = \"square.geo\"\n" + std::string(kConditions));
  const auto r = test::run_keller("solve " + dir + "/ok.toml -o " + dir + "/ok.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  H5File f(dir + "/ok.h5", H5File::Mode::Read);
  EXPECT_TRUE(f.exists("/mesh/nodes"));
  EXPECT_TRUE(f.exists("/mesh/boundaries/inflow"));
}

// The shipped Newtonian contraction, a branch in Re from 1 to 3 with the spectrum of every point,
// restarted from its stop at Re = 2 and exported: slow flow through a contraction is steady and
// stable (every eigenvalue of J phi = sigma B phi decays, converged to 1e-8), the observables are
// columns, and the restart continues where the stop is. (At Re = 0 the Newtonian B is zero and a
// spectrum has no finite eigenvalue: refused, FlowEvolve.AStokesFlowHasNoDynamicsAndIsRefusedNamingRe.)
TEST(FlowInput, AFlowBranchHasSpectraRestartsAndExports) {
  const std::string dir = test::scratch_dir("flow_branch");
  const std::string scene = test::source_path("runs/scenes/flow_contraction_newtonian.toml");
  const std::string re = " --set parameters.Re=1 --set continuation.parameter=Re --set stability.enabled=true";
  auto r = test::run_keller("trace " + scene + re + " --set continuation.upper=3 --set continuation.stops=[2.0] -o " +
                            dir + "/a.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const BranchTable a = read_branch_table(dir + "/a.h5");
  ASSERT_GE(a.rows.rows(), 3);
  for (const char* c : {"X_R", "Psi_R", "C", "unstable", "sigma1_re"}) EXPECT_NO_THROW(a.column(c)) << c;
  for (int i = 0; i < a.rows.rows(); ++i) {
    EXPECT_EQ(a.rows(i, a.column("unstable")), 0.0) << "row " << i;
    EXPECT_GT(a.rows(i, a.column("sigma1_re")), 0.0) << "row " << i;  // J phi = sigma B phi: decaying
    EXPECT_LT(a.rows(i, a.column("eig_residual")), 1e-8) << "row " << i;
  }
  EXPECT_DOUBLE_EQ(a.rows(a.rows.rows() - 1, a.column("Re")), 3.0);
  // inertia shortens the salient corner vortex (seen in experiments from Re = 0.1, Alves et al.'s
  // 2004 visualisations): X_R falls along the whole branch
  for (int i = 1; i < a.rows.rows(); ++i) EXPECT_LT(a.rows(i, a.column("X_R")), a.rows(i - 1, a.column("X_R")));
  r = test::run_keller("trace " + scene + re + " --set continuation.upper=4 --restart " + dir + "/a.h5:stop1 -o " +
                       dir + "/b.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const BranchTable b = read_branch_table(dir + "/b.h5");
  EXPECT_DOUBLE_EQ(b.rows(0, b.column("Re")), 2.0);
  EXPECT_DOUBLE_EQ(b.rows(b.rows.rows() - 1, b.column("Re")), 4.0);
  r = test::run_keller("export " + dir + "/a.h5 --xdmf");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(fs::exists(dir + "/a.xdmf"));
}
