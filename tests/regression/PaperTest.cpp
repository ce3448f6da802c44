// runs/paper/make_all.py end to end on its cheapest figure: `--only fig01` runs only the study
// that figure reads (seven steady-shear branches of three unknowns, about a second), draws it,
// and a second run skips every task by its hash. What the study collected along the way is held
// to the closed forms: eta_p at 1 1/s (the stop log10_rate = 0) is the Cross law for Owens and
// 1/f (Cardano) for FENE-P at W = lambda_0 r = 0.263, within the corrector's tolerance carried to
// the viscosity (1e-8 (1 + 1/W), tests/regression/SteadyShearTraceTest.cpp). A figure that does
// not exist is refused before any work.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "support/ShearClosedForms.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

test::CommandResult make_all(const std::string& dir, const std::string& args) {
  // the script runs keller through --keller; run_keller's shell runs the script instead
  const std::string script = test::python_command() + " " + test::source_path("runs/paper/make_all.py");
  const std::string cmd = script + " --keller " + KELLER_BINARY + " --data " + dir + "/data --figures " + dir +
                          "/figures --jobs 2 " + args + " > " + dir + "/out.txt 2> " + dir + "/err.txt";
  test::CommandResult r;
  r.exit_code = WEXITSTATUS(std::system(cmd.c_str()));
  std::ifstream o(dir + "/out.txt"), e(dir + "/err.txt");
  r.out.assign(std::istreambuf_iterator<char>(o), {});
  r.err.assign(std::istreambuf_iterator<char>(e), {});
  return r;
}

}  // namespace

TEST(Paper, OneFigureRunsItsStudyAndSkipsItTheSecondTime) {
  const std::string dir = test::scratch_dir("paper_fig01");
  test::CommandResult r = make_all(dir, "--only fig01");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("study steady_shear"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("study wi"), std::string::npos) << "only the study fig01 reads: " << r.out;
  EXPECT_GT(fs::file_size(dir + "/figures/fig01_shear_viscosity.png"), 10000u);
  EXPECT_FALSE(fs::exists(dir + "/figures/fig01_shear_viscosity.png.part"));

  const OwensParameters o;
  int checked = 0;
  for (const auto& row : test::read_table(dir + "/data/steady_shear/steady_shear.csv")) {
    ASSERT_EQ(row.at("status"), "done") << row.at("name");
    const double eta_p = std::stod(row.at("eta_p@0")), W = std::stod(row.at("Wi_local@0"));
    EXPECT_NEAR(W, 0.263, 1e-14);
    const double expected = row.at("fluid.model") == "owens"
                                ? (test::cross_viscosity(o, 1.0) - o.eta_s) / o.eta_p0
                                : test::fene_p_viscosity_ratio(W, std::stod(row.at("parameters.b")));
    EXPECT_NEAR(eta_p, expected, 1e-8 * (1 + 1 / W) * expected) << row.at("name");
    ++checked;
  }
  EXPECT_EQ(checked, 7);

  r = make_all(dir, "--only fig01");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("7 tasks, 7 done before, 0 to run"), std::string::npos) << r.out;
}

TEST(Paper, AnUnknownFigureIsRefused) {
  const std::string dir = test::scratch_dir("paper_unknown");
  const test::CommandResult r = make_all(dir, "--only fig17");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("no figure fig17"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/data/steady_shear"));
}
