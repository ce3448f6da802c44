// A flow's own inputs through the real driver, and the capabilities every problem has on it
// (a branch in Re with its spectra, a restart from a labelled point, export for ParaView): a mesh keller cannot use
// (triangles, a damaged .msh, a .geo with an error or an undeclared parameter) and boundary conditions that do not
// match the mesh are refused before any work, exit code 2, with a message naming the file and
// what to change, and nothing is written; the shipped Newtonian contraction solves and stores
// the mesh the .geo made.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

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

// A mesh file changed under the same name is another problem: a branch traced on the old content
// is not restarted on the new one (the stored physics record holds a hash of the file's bytes),
// while the unchanged file restarts. Here the .geo's square becomes 1.5 long with the same
// elements, so the unknowns agree and only the content tells the two apart.
TEST(FlowInput, AMeshFileChangedUnderItsNameIsNotRestartedFrom) {
  const std::string dir = test::scratch_dir("flow_mesh_content");
  const std::string geo = std::string(kSquareGeo) + "Recombine Surface{1};\nMesh.ElementOrder = 2;\n";
  write(dir + "/square.geo", geo);
  write(dir + "/s.toml", "[problem]\ntype = \"flow\"\n[mesh]\ngeo = \"square.geo\"\n" + std::string(kConditions) +
                             "[parameters]\nRe = 1.0\n[continuation]\nparameter = \"Re\"\nupper = 2.0\n");
  const auto first = test::run_keller("trace " + dir + "/s.toml -o " + dir + "/a.h5");
  ASSERT_EQ(first.exit_code, 0) << first.out << first.err;
  const auto same = test::run_keller("trace " + dir + "/s.toml --restart " + dir +
                                     "/a.h5:last --set continuation.upper=3 -o " + dir + "/b.h5");
  EXPECT_EQ(same.exit_code, 0) << same.out << same.err;
  std::string longer = geo;
  longer.replace(longer.find("L = {1,"), 7, "L = {1.5,");
  write(dir + "/square.geo", longer);
  const auto changed = test::run_keller("trace " + dir + "/s.toml --restart " + dir +
                                        "/a.h5:last --set continuation.upper=3 -o " + dir + "/c.h5");
  EXPECT_EQ(changed.exit_code, 2) << changed.out << changed.err;
  EXPECT_NE(changed.err.find("mesh.geo:content"), std::string::npos) << changed.err;
  EXPECT_FALSE(fs::exists(dir + "/c.h5"));
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

// python3 -m keller.plot flow draws the mesh and the flow of a solve and of a branch. Its stream
// function is its own Python implementation of the least squares keller's `stream-function`
// observable solves: on the Newtonian contraction, with psi = 0 on the same wall, its corner
// vortex's extremum is keller's Psi_R times the flow rate to 1e-8 (both solve the same linear
// system; rounding and the solvers' accuracy differ).
TEST(FlowInput, FlowFiguresOfASolveAndOfABranch) {
  const std::string dir = test::scratch_dir("flow_figures");
  auto r = test::run_keller("solve " + test::source_path("runs/scenes/flow_contraction_newtonian.toml") + " -o " + dir +
                            "/c.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto at = r.out.find("Psi_R = ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const double psi_r = std::stod(r.out.substr(at + 8));
  const std::string py = test::python_module("keller.plot flow") + " ";
  const std::string out = dir + "/psi.txt";
  std::string cmd = py + dir + "/c.h5 --psi-zero upstream_wall --xlim -8 6 -o " + dir + "/c.png > " + out;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_GT(fs::file_size(dir + "/c.png"), 20000u);
  // "psi: q = Q, extremum of the other sign E q, ..."
  const std::string text = test::file_contents(out);
  const auto q_at = text.find("q = "), e_at = text.find("other sign ");
  ASSERT_TRUE(q_at != std::string::npos && e_at != std::string::npos) << text;
  const double q = std::stod(text.substr(q_at + 4)), e = std::stod(text.substr(e_at + 11));
  EXPECT_NEAR(q, 1.0, 1e-5);  // the flow rate of the half channel, up to the discrete curl's error
  EXPECT_NEAR(e * q, psi_r, 1e-8 * psi_r);

  r = test::run_keller("trace " + test::source_path("runs/scenes/flow_stenosis.toml") +
                       " --set continuation.upper=30 --set continuation.stops=[25.0] -o " + dir + "/s.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  cmd = py + dir + "/s.h5 --row last --xlim -3 7 -o " + dir + "/s.png > " + out;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_GT(fs::file_size(dir + "/s.png"), 20000u);
  EXPECT_NE(test::file_contents(out).find("other sign"), std::string::npos);
  // a row without a stored solution is refused, naming the rows that have one
  cmd = py + dir + "/s.h5 --row 1 -o " + dir + "/t.png 2> " + out;
  EXPECT_NE(std::system(cmd.c_str()), 0);
  EXPECT_NE(test::file_contents(out).find("stored rows"), std::string::npos) << test::file_contents(out);
  EXPECT_FALSE(fs::exists(dir + "/t.png"));
}

// The stenosis in the whole channel (stenosis.geo with full = 1, no symmetry line): its symmetric
// flow is the half channel's (the force on the stenosed wall at Re = 100 agrees to 1e-6, and the
// lower wall's is its mirror image), and it loses its symmetry at a pitchfork that the branch
// locates at Re = 136.1 on f = 1 (138.1 on f = 2; 136.1 with the outflow 60 instead of 20
// half-widths behind the stenosis; docs/geometries.md): asserted within [134, 140].
TEST(FlowInput, TheStenosisInTheWholeChannelLosesItsSymmetryAtAPitchfork) {
  const std::string dir = test::scratch_dir("flow_stenosis_full");
  auto r =
      test::run_keller("trace " + test::source_path("runs/scenes/flow_stenosis_full.toml") + " -o " + dir + "/full.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  r = test::run_keller("trace " + test::source_path("runs/scenes/flow_stenosis.toml") + " -o " + dir + "/half.h5");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const BranchTable full = read_branch_table(dir + "/full.h5"), half = read_branch_table(dir + "/half.h5");
  // a column at a requested value (a stop, or the end at the upper bound)
  auto at = [](const BranchTable& t, double re, const char* column) -> double {
    for (int i = 0; i < t.rows.rows(); ++i) {
      const double kind = t.rows(i, t.column("kind"));
      if ((kind == 2 || kind == 6) && t.rows(i, t.column("Re")) == re) return t.rows(i, t.column(column));
    }
    return NAN;
  };
  const double fy = at(full, 100.0, "F_y");
  EXPECT_NEAR(fy, at(half, 100.0, "F_y"), 1e-6 * std::abs(fy));
  EXPECT_NEAR(at(full, 100.0, "F_y_lower"), -fy, 1e-6 * std::abs(fy));
  EXPECT_NEAR(at(full, 100.0, "L_r"), at(half, 100.0, "L_r"), 1e-6);
  EXPECT_NEAR(at(full, 100.0, "L_r_lower"), at(half, 100.0, "L_r"), 1e-6);
  int bps = 0;
  for (int i = 0; i < full.rows.rows(); ++i)
    if (full.rows(i, full.column("kind")) == 5) {
      ++bps;
      EXPECT_GT(full.rows(i, full.column("Re")), 134.0);
      EXPECT_LT(full.rows(i, full.column("Re")), 140.0);
    }
  EXPECT_EQ(bps, 1);

  // --switch onto the asymmetric branches, one to each side: they leave the symmetric flow (the
  // forces on the two stenosed walls differ by a fifth at Re = 160) and are each other's mirror
  // images (upper wall's force on one = lower wall's on the other, to the corrector's tolerance).
  // Until the located point kept its bracket's tangent, the switch took the branch point's own,
  // singular-system tangent, which is J's null vector: orthogonal to it the switch went back along
  // the symmetric branch (to Re = 0).
  std::map<int, BranchTable> side;
  for (int direction : {1, -1}) {
    const std::string out = dir + "/switched" + std::to_string(direction + 1) + ".h5";
    r = test::run_keller("trace " + test::source_path("runs/scenes/flow_stenosis_full.toml") + " --switch " + dir +
                         "/full.h5:bp1 --switch-direction " + std::to_string(direction) + " -o " + out);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    side.emplace(direction, read_branch_table(out));
  }
  const double up = at(side.at(1), 160.0, "F_y"), low = at(side.at(1), 160.0, "F_y_lower");
  EXPECT_GT(std::abs(up + low), 0.2 * std::abs(up)) << up << " " << low;
  EXPECT_NEAR(at(side.at(-1), 160.0, "F_y"), -low, 1e-6 * std::abs(low));
  EXPECT_NEAR(at(side.at(-1), 160.0, "F_y_lower"), -up, 1e-6 * std::abs(up));
  EXPECT_NEAR(at(side.at(-1), 160.0, "L_r"), at(side.at(1), 160.0, "L_r_lower"), 1e-6);
}
