// The steady-shear viscosity of figure 1 of the reference study as keller makes it: the scene
// runs/scenes/steady_shear_owens.toml (and its FENE-P variant) through `keller trace` in log10 of
// the shear rate, every row's eta_p against the closed forms (the Cross law of Owens, Cardano's
// root for FENE-P), over the whole range of rates; and the scene's bad input.
//
// Tolerance: the corrector stops at |F|_inf <= 1e-10 (newton.residual_tolerance; F = lambda R is
// dimensionless and J = I + O(W) near rest), which leaves M_xy, of size W / f^2, with an error
// of about 1e-10 |J^-1|; the viscosity eta_p / eta_p0 = f M_xy / W (f = 1 but for FENE-P) then
// has a relative error of about 1e-10 (1 + W) / W. The test allows 1e-8 (1 + 1 / W): a hundred
// times that.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "continuation/output/BranchFile.hpp"
#include "support/ShearClosedForms.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

const std::string kScene = "runs/scenes/steady_shear_owens.toml";

BranchTable trace(const std::string& name, const std::string& overrides) {
  const std::string dir = test::scratch_dir("steady_shear_" + name);
  const test::CommandResult r = test::run_keller("trace " + test::source_path(kScene) + " -o " + dir +
                                                 "/b.h5 --set output.xdmf=false" + overrides);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return read_branch_table(dir + "/b.h5");
}

// Checks the branch spans the scene's rates, 1e-3 to 1e4 1/s, and returns the largest relative
// deviation of eta_p from `closed(W, r)` over its rows.
template <class Closed>
double deviation(const BranchTable& t, Closed closed) {
  const int rate = t.column("rate"), W = t.column("Wi_local"), eta_p = t.column("eta_p");
  EXPECT_NEAR(t.rows(0, rate), 1e-3, 1e-15);
  EXPECT_NEAR(t.rows(t.rows.rows() - 1, rate), 1e4, 1e-8);
  EXPECT_GE(t.rows.rows(), 20);
  double worst = 0;
  for (int i = 0; i < t.rows.rows(); ++i) {
    const double w = t.rows(i, W), r = t.rows(i, rate), expected = closed(w, r);
    EXPECT_NEAR(t.rows(i, W), 0.263 * r, 1e-14 * r) << "lambda_0 = Wi W / U0 = 0.263 s";
    EXPECT_NEAR(t.rows(i, eta_p), expected, 1e-8 * (1 + 1 / w) * expected) << "row " << i << ", rate " << r;
    worst = std::max(worst, std::abs(t.rows(i, eta_p) / expected - 1));
  }
  return worst;
}

}  // namespace

TEST(SteadyShearTrace, OwensFollowsTheCrossLaw) {
  const OwensParameters o;
  for (const char* form : {"conformation", "log-conformation"}) {
    const BranchTable t = trace(std::string("owens_") + form, std::string(" --set fluid.formulation=") + form);
    const double worst = deviation(t, [&](double, double r) {
      return (test::cross_viscosity(o, std::hypot(r, o.rate_floor)) - o.eta_s) / o.eta_p0;
    });
    std::printf("Owens (%s): %ld rows, eta_p / eta_p0 from %.4g to %.4g, largest relative deviation %.1e\n", form,
                static_cast<long>(t.rows.rows()), t.rows(0, t.column("eta_p")),
                t.rows(t.rows.rows() - 1, t.column("eta_p")), worst);
  }
}

TEST(SteadyShearTrace, FenePFollowsItsClosedForm) {
  for (double b : {2.0, 100.0}) {
    const BranchTable t = trace("fene_p_" + std::to_string(static_cast<int>(b)),
                                " --set fluid.model=fene-p --set parameters.b=" + std::to_string(b));
    const double worst = deviation(t, [&](double W, double) { return test::fene_p_viscosity_ratio(W, b); });
    std::printf("FENE-P b = %g: %ld rows, largest relative deviation %.1e\n", b, static_cast<long>(t.rows.rows()),
                worst);
  }
}

TEST(SteadyShearTrace, BadInputNamesTheKey) {
  const std::string dir = test::scratch_dir("steady_shear_bad");
  const std::string base = "trace " + test::source_path(kScene) + " -o " + dir + "/b.h5";
  // a Newtonian fluid has no conformation: not a choice of this problem's fluid.model
  test::CommandResult r = test::run_keller(base + " --set fluid.model=newtonian");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("fluid.model"), std::string::npos) << r.err;
  r = test::run_keller(base + " --set parameters.b=5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("parameters.b"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fene-p"), std::string::npos) << r.err;
}
