// Inflow profiles: flow rate, the power-law shape, and the fully developed profile of the
// fluids against what is known of it.
#include <gtest/gtest.h>

#include <cmath>

#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/InflowProfile.hpp"
#include "problems/laws/SteadyFlows.hpp"

using namespace keller;

namespace {
double mean_of(const InflowProfile& p, double U, const std::function<double(double)>& eta) {
  // 400-point midpoint rule is plenty for a check at 1e-5
  std::vector<double> y, u, d;
  const int n = 400;
  for (int i = 0; i < n; ++i) y.push_back(p.y_lo + (p.y_hi - p.y_lo) * (i + 0.5) / n);
  p.evaluate(y, U, eta, u, d);
  double s = 0;
  for (double v : u) s += v;
  return s / n;
}
}  // namespace

TEST(InflowProfile, PowerLawShapeAndFlowRate) {
  for (double n : {0.3, 0.5, 1.0}) {
    InflowProfile p{ProfileKind::PowerLaw, 0.0, 1.0, n};
    std::vector<double> u, d;
    p.evaluate({0.5, 0.0, 1.0}, 2.0, {}, u, d);
    EXPECT_NEAR(u[0] / 2.0, (2 * n + 1) / (n + 1), 1e-14);  // u_max / u_mean
    EXPECT_EQ(u[1], 0.0);
    EXPECT_EQ(u[2], 0.0);
    EXPECT_NEAR(mean_of(p, 2.0, {}), 2.0, 2e-5 * 2.0);
  }
}

TEST(InflowProfile, FullyDevelopedNewtonianIsParabolic) {
  InflowProfile fd{ProfileKind::FullyDeveloped, -2.0, 2.0, 0.5}, par{ProfileKind::Parabolic, -2.0, 2.0, 0.5};
  const auto eta = [](double) { return 1.0; };
  std::vector<double> y = {-1.9, -0.3, 0.0, 0.7, 1.99}, u1, d1, u2, d2;
  fd.evaluate(y, 1.3, eta, u1, d1);
  par.evaluate(y, 1.3, eta, u2, d2);
  for (size_t i = 0; i < y.size(); ++i) {
    EXPECT_NEAR(u1[i], u2[i], 1e-12);
    EXPECT_NEAR(d1[i], d2[i], 1e-12);
  }
  const FullyDevelopedProfile p(eta, 2.0, 1.3);
  EXPECT_NEAR(p.pressure_gradient(), 3 * 1.3 / 4.0, 1e-13);  // G = 3 U eta / H^2
}

// A shear-thinning fluid has a flatter profile at the same flow rate, and its wall shear stress
// G H balances the pressure gradient.
TEST(InflowProfile, FullyDevelopedShearThinningFluids) {
  OwensParameters o;
  const double Gamma = 4.95e-4, Wi = 0.5;
  for (FluidModel m : {FluidModel::FeneP, FluidModel::Owens}) {
    const double beta = m == FluidModel::Owens ? o.beta() : 0.1;
    const auto eta = [&](double g) { return shear_viscosity(m, g, Wi, Gamma, beta, LawConstants<double>{20.0}, o); };
    InflowProfile p{ProfileKind::FullyDeveloped, 0.0, 1.0, 0.5};
    EXPECT_NEAR(mean_of(p, Gamma, eta), Gamma, 2e-5 * Gamma) << to_string(m);
    std::vector<double> u, d;
    p.evaluate({0.5, 0.0}, Gamma, eta, u, d);
    EXPECT_LT(u[0], 1.5 * Gamma) << to_string(m);  // flatter than the parabola
    EXPECT_GT(u[0], Gamma);
    const FullyDevelopedProfile fd(eta, 0.5, Gamma);
    EXPECT_NEAR(eta(std::abs(d[1])) * std::abs(d[1]), fd.pressure_gradient() * 0.5, 1e-10 * fd.pressure_gradient());
  }
}

// A shear stress with a maximum has no unique fully developed profile once the flow needs more
// than the maximum: refused (std::domain_error), not a profile picked silently. tau(g) = g / (1 +
// g^2) + 0.02 g rises to 0.52 at g ~ 1, falls to 0.28, and rises again from g ~ 7: at mean velocity 0.05
// (half-width 1) the wall stress stays below 0.28 and the profile exists; at 5 the flow
// rate jumps over the requested one as the pressure gradient passes the maximum; and a profile
// whose shear rates run past the maximum (the eta of a Johnson-Segalman-like fluid) is refused by
// the scan of tau up to the wall.
TEST(InflowProfile, AShearStressWithAMaximumIsRefused) {
  const auto eta = [](double g) { return 1.0 / (1.0 + g * g) + 0.02; };
  EXPECT_NO_THROW(FullyDevelopedProfile(eta, 1.0, 0.05));
  for (double U : {5.0, 50.0}) {
    try {
      FullyDevelopedProfile(eta, 1.0, U);
      ADD_FAILURE() << "a non-monotone shear stress was accepted at U = " << U;
    } catch (const std::domain_error& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what.find("shear stress falls") != std::string::npos ||
                  what.find("flow rate jumps") != std::string::npos)
          << what;
    }
  }
  // a monotone one is not refused however fast the flow (Giesekus at alpha = 1/2, whose polymer
  // stress levels off at G_p, with a little solvent: wall shear rates of order 1e4)
  const LawConstants<double> c{100.0, 0.5};
  const auto giesekus = [&](double g) { return shear_viscosity(FluidModel::Giesekus, g, 1.0, 1.0, 0.05, c, {}); };
  for (double U : {1.0, 1e3}) EXPECT_NO_THROW(FullyDevelopedProfile(giesekus, 1.0, U)) << U;
}
