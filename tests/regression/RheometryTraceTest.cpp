// The rheometry scenes as a user runs them: runs/scenes/{steady_shear,planar_extension,
// uniaxial_extension}_ptt.toml through `keller trace` in log10 of the rate, for the linear PTT
// of the scenes and, by --set, the other new laws, every row against the closed forms of
// problems/laws/SteadyFlows (themselves checked against independent solutions in
// ConstitutiveLawTest); and the scenes' bad input.
//
// Tolerance: the scenes' corrector stops at |F|_inf <= 1e-13 (newton.residual_tolerance; F =
// lambda R is dimensionless, J = I + O(W) near rest), which leaves the conformation with an error
// of about 1e-13 |J^-1|; stresses of size W (shear) or 1 + W (extension) then carry a relative
// error of about 1e-13 (1 + W) / W. The test allows 1e-10 + 1e-13 / W: the 1e-10, and
// the corrector's own bound where W is small.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "continuation/output/BranchFile.hpp"
#include "problems/laws/SteadyFlows.hpp"
#include "support/LawStates.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

struct Law {
  const char* name;
  FluidModel model;
  LawConstants<double> c;
  const char* overrides;
};

const Law kLaws[] = {
    {"ptt_linear", FluidModel::PttLinear, {100.0, 0.0, 0.25}, ""},
    {"ptt_linear_xi", FluidModel::PttLinear, {100.0, 0.0, 0.25, 0.1}, " --set parameters.xi=0.1"},
    {"ptt_exponential",
     FluidModel::PttExponential,
     {100.0, 0.0, 0.25},
     " --set fluid.model=\"ptt-exponential\" --set fluid.formulation=\"log-conformation\""},
    {"giesekus",
     FluidModel::Giesekus,
     {100.0, 0.3},
     " --set fluid.model=\"giesekus\" --set parameters.alpha=0.3"},  // the scene's epsilon is the default
    {"fene_cr", FluidModel::FeneCr, {10.0}, " --set fluid.model=\"fene-cr\" --set parameters.b=10"},
};

BranchTable trace(const std::string& scene, const std::string& name, const std::string& overrides,
                  test::CommandResult* out = nullptr) {
  const std::string dir = test::scratch_dir("rheometry_" + scene + "_" + name);
  const test::CommandResult r = test::run_keller("trace " + test::source_path("runs/scenes/" + scene + "_ptt.toml") +
                                                 " -o " + dir + "/b.h5 --set output.xdmf=false" + overrides);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (out) *out = r;
  return read_branch_table(dir + "/b.h5");
}

}  // namespace

TEST(RheometryTrace, EveryLawFollowsItsClosedFormsOverEightDecades) {
  for (const Law& l : kLaws)
    for (const std::string scene : {"steady_shear", "planar_extension", "uniaxial_extension"}) {
      const BranchTable t = trace(scene, l.name, l.overrides);
      ASSERT_GE(t.rows.rows(), 60) << scene << " " << l.name;
      const int W = t.column("Wi_local"), rate = t.column("rate");
      EXPECT_NEAR(t.rows(0, rate), 0.1, 1e-15);
      EXPECT_NEAR(t.rows(t.rows.rows() - 1, rate), 1e5, 1e-9);
      double worst = 0;
      for (int i = 0; i < t.rows.rows(); ++i) {
        const double w = t.rows(i, W), r = t.rows(i, rate);
        EXPECT_NEAR(w, 0.01 * r, 1e-14 * r) << "lambda_0 = Wi / rate_scale = 10 ms";
        auto check = [&](const char* column, double expected) {
          const double got = t.rows(i, t.column(column));
          EXPECT_NEAR(got, expected, (1e-10 + 1e-13 / w) * std::abs(expected))
              << scene << " " << l.name << " row " << i << " " << column << " W = " << w;
          worst = std::max(worst, std::abs(got / expected - 1));
        };
        if (scene == "steady_shear") {
          check("eta_p", polymer_shear_ratio(l.model, w, l.c));
          // psi1_p at W < 1e-2 carries eps / (2 W^2) of rounding (RheometryTest): checked above it
          if (w > 1e-2) {
            const Conformation<double> s = test::closed_stress(l.model, l.c, steady_shear(l.model, w, l.c));
            check("psi1_p", (s.xx - s.yy) / (2 * w * w));
          }
        } else {
          const Extension kind = scene == "planar_extension" ? Extension::Planar : Extension::Uniaxial;
          const Conformation<double> s = test::closed_stress(l.model, l.c, steady_extension(l.model, kind, w, l.c));
          check("eta_e_p", (s.xx - s.yy) / w);
        }
      }
      std::printf("%s %s: %ld rows, largest relative deviation %.1e\n", scene.c_str(), l.name,
                  static_cast<long>(t.rows.rows()), worst);
    }
}

TEST(RheometryTrace, BadInputNamesTheKey) {
  const std::string dir = test::scratch_dir("rheometry_bad");
  for (const std::string scene : {"steady_shear", "planar_extension"}) {
    const std::string base =
        "trace " + test::source_path("runs/scenes/" + scene + "_ptt.toml") + " -o " + dir + "/b.h5";
    // the slip has no log form; alpha is Giesekus'; a Newtonian fluid has no conformation
    test::CommandResult r =
        test::run_keller(base + " --set fluid.formulation=\"log-conformation\" --set parameters.xi=0.2");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("parameters.xi"), std::string::npos) << r.err;
    r = test::run_keller(base + " --set parameters.alpha=0.2");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("parameters.alpha"), std::string::npos) << r.err;
    r = test::run_keller(base + " --set fluid.model=\"newtonian\"");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("fluid.model"), std::string::npos) << r.err;
    r = test::run_keller(base + " --set parameters.epsilon=-1");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("parameters.epsilon"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/b.h5"));
  }
}
