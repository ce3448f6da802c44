// The keller program end to end: the shipped default scene solves and writes HDF5 + XDMF;
// every kind of malformed scene stops the run with its own clear error, a non-zero exit code
// and no output file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

TEST(CommandLine, SolvesTheDefaultScene) {
  const std::string dir = test::scratch_dir("cli_solve");
  const auto r =
      test::run_keller("solve " + test::source_path("runs/scenes/channel_stokes.toml") + " -o " + dir + "/out.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // the scene's keys that differ from their defaults printed: the mesh, not the Newtonian fluid (the default)
  EXPECT_NE(r.out.find("[mesh]\nname = \"M2\"\n"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("[fluid]"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("# default"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("iter"), std::string::npos);  // Newton table printed
  ASSERT_TRUE(fs::exists(dir + "/out.h5"));
  ASSERT_TRUE(fs::exists(dir + "/out.xdmf"));
  EXPECT_FALSE(fs::exists(dir + "/out.h5.part"));
  H5File f(dir + "/out.h5", H5File::Mode::Read);
  EXPECT_NE(f.read_string("/scene").find("name = \"M2\""), std::string::npos);
  const double Gamma = f.read_double_attribute("/solution/parameters", "Gamma");
  EXPECT_NEAR(f.read_double_attribute("/solution/observables", "dP"), 60 * Gamma, 1e-10 * 60 * Gamma);
  EXPECT_EQ(f.read_string_attribute("/solution/fields/velocity", "basis"), "Q2");
  EXPECT_EQ(f.read_string_attribute("/solution/fields/pressure", "basis"), "P1disc");
  long rows = 0, cols = 0;
  f.read_matrix("/mesh/nodes", &rows, &cols);
  EXPECT_EQ(rows, 3025);
  EXPECT_EQ(cols, 2);
  std::ifstream x(dir + "/out.xdmf");
  const std::string xdmf((std::istreambuf_iterator<char>(x)), std::istreambuf_iterator<char>());
  EXPECT_NE(xdmf.find("Quadrilateral_9"), std::string::npos);
  EXPECT_NE(xdmf.find("out.h5:/solution/fields/xdmf/velocity_vector"), std::string::npos);
  EXPECT_NE(xdmf.find("<Attribute Name=\"p\" AttributeType=\"Scalar\" Center=\"Cell\">"), std::string::npos);
}

namespace {

struct BadScene {
  std::string name, text, expected;
};

void expect_rejected(const std::string& scene_path, const std::string& expected, const std::string& dir) {
  const std::string out = dir + "/out.h5";
  const auto r = test::run_keller("solve " + scene_path + " -o " + out);
  EXPECT_EQ(r.exit_code, 2) << scene_path;
  EXPECT_NE(r.err.find(expected), std::string::npos) << "stderr was: " << r.err;
  EXPECT_NE(r.err.find("keller: error"), std::string::npos);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".part"));
  EXPECT_FALSE(fs::exists(dir + "/out.xdmf"));
}

}  // namespace

TEST(CommandLine, MalformedScenesGetTheirOwnErrors) {
  const std::string dir = test::scratch_dir("cli_bad");
  const std::vector<BadScene> cases = {
      {"unknown_key.toml", "[mesh]\nnme = \"M1\"\n",
       "bad/unknown_key.toml:2: unknown key 'mesh.nme'; keys allowed in [mesh]: name,"},
      {"wrong_type.toml", "[mesh]\nname = 3\n", "key 'mesh.name' must be a string, got an integer (3)"},
      {"negative_length.toml", "[geometry]\nupstream_length = -7.0\n",
       "key 'geometry.upstream_length' = -7 is out of range: must be > 0"},
      {"not_toml.toml", "this is not toml\n", "not valid TOML"},
      {"bad_choice.toml", "[fluid]\nmodel = \"water\"\n", "key 'fluid.model' = \"water\" is not one of: newtonian"},
      {"bad_problem.toml", "[problem]\ntype = \"teapot\"\n", "unknown problem type 'teapot'"},
      {"unknown_section.toml", "[meshh]\nname = \"M1\"\n", "unknown section [meshh]"},
      {"preset_with_sizes.toml", "[mesh]\nname = \"M1\"\nny_fluid = 4\n", "explicit sizes need mesh.name = \"custom\""},
  };
  fs::create_directories(dir + "/bad");
  for (const auto& c : cases) {
    const std::string path = dir + "/bad/" + c.name;
    std::ofstream(path) << c.text;
    SCOPED_TRACE(c.name);
    expect_rejected(path, c.expected, dir);
  }
  expect_rejected(dir + "/missing.toml", "scene file '" + dir + "/missing.toml' does not exist", dir);
  // an output directory that does not exist is caught before any work
  const auto r = test::run_keller("solve " + test::source_path("runs/scenes/channel_stokes.toml") + " -o " + dir +
                                  "/no/such/dir/out.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

TEST(CommandLine, HelpListsEveryKey) {
  const auto r = test::run_keller("solve --help-scene");
  ASSERT_EQ(r.exit_code, 0);
  for (const char* key : {"[geometry]", "upstream_length", "[newton]", "residual_tolerance", "[linear_solver]",
                          "ordering", "bratu1d", "[parameters]", "Gamma"})
    EXPECT_NE(r.out.find(key), std::string::npos) << key;
  const auto h = test::run_keller("solve --help");
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("--output"), std::string::npos);
  const auto none = test::run_keller("solve");
  EXPECT_EQ(none.exit_code, 2);
}

// A mesh the machine cannot hold is refused from its keys alone, before anything is built or
// written, naming the key that sets its size and the memory it would take (a lower estimate:
// 3e8 elements at 90 kB each, 27 TB), not run into an allocation failure minutes later.
TEST(CommandLine, AMeshTooLargeForTheMachineIsRefusedBeforeItIsBuilt) {
  const std::string dir = test::scratch_dir("cli_memory");
  for (const std::string command : {"solve", "trace"}) {
    SCOPED_TRACE(command);
    const auto r = test::run_keller(command + " " + test::source_path("runs/scenes/collapsible_oldroyd_b_gamma.toml") +
                                    " --set mesh.name='\"custom\"' --set mesh.nx_upstream=10000 --set "
                                    "mesh.nx_deformable=10000 --set mesh.nx_downstream=10000 --set mesh.ny_fluid=10000 "
                                    "--set mesh.ny_solid=100 -o " +
                                    dir + "/big.h5");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("key 'mesh.nx_upstream'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("needs at least 2.71e+04 GB of memory to solve (301000000 elements)"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(dir + "/big.h5"));
    EXPECT_FALSE(fs::exists(dir + "/big.h5.part"));
  }
}
