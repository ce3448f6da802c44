// Constitutive laws against closed forms: steady simple shear and planar elongation states make
// the pointwise conformation equation vanish, and stresses and viscosities are the known ones.
#include <gtest/gtest.h>

#include <cmath>

#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/LogConformation.hpp"

using namespace keller;

namespace {

// Residual of the steady homogeneous conformation equation at a closed-form state.
double shear_residual(FluidModel model, const SteadyConformation& s, double gdot, double lambda, double b,
                      bool dynamic) {
  const double L[2][2] = {{0.0, gdot}, {0.0, 0.0}};
  const Conformation<double> M{s.xx, s.xy, s.yy, s.zz};
  const double f = peterlin(model, dynamic, M, b);
  const Conformation<double> r = conformation_rate(M, L, f, 1.0 / lambda);
  return std::max({std::abs(r.xx), std::abs(r.xy), std::abs(r.yy), dynamic ? std::abs(r.zz) : 0.0});
}

}  // namespace

TEST(ConstitutiveLaw, OldroydBSimpleShear) {
  for (double W : {0.0, 0.3, 1.0, 7.5}) {
    const SteadyConformation s = steady_shear(FluidModel::OldroydB, W, 0.0);
    EXPECT_EQ(s.xx, 1 + 2 * W * W);
    EXPECT_EQ(s.xy, W);
    EXPECT_EQ(s.yy, 1.0);
    EXPECT_LT(shear_residual(FluidModel::OldroydB, s, W, 1.0, 0.0, false), 1e-12 * s.xx);  // W = lambda gdot
    // polymer shear stress = (1 - beta) Gamma / Wi * W = (1 - beta) gdot: constant viscosity
    const double beta = 0.59, Gamma = 1.0, Wi = 0.7, gdot = W * Gamma / Wi;
    const Conformation<double> tp =
        polymer_stress(Conformation<double>{s.xx, s.xy, s.yy, 1.0}, 1.0, (1 - beta) * Gamma / Wi);
    EXPECT_NEAR(tp.xy, (1 - beta) * gdot, 1e-12 * std::max(1.0, gdot));
    EXPECT_NEAR(tp.xx, 2 * (1 - beta) * Wi / Gamma * gdot * gdot, 1e-12 * std::max(1.0, gdot * gdot));
  }
}

// method.md's table for b = 50: W = 1, 5, 20 -> f = 1.012993, 2.151823 ...; M_xx = 2.91120 ...
TEST(ConstitutiveLaw, FenePSimpleShearMatchesThePublishedTable) {
  const double b = 50;
  const struct {
    double W, f, Mxx;
  } table[] = {{1, 1.012993, 2.91120}, {5, 1.222895, 28.15798}, {20, 2.151823, 80.75638}};
  for (const auto& row : table) {
    const SteadyConformation s = steady_shear(FluidModel::FeneP, row.W, b);
    EXPECT_NEAR(s.f * s.f * (s.f - 1), 2 * row.W * row.W / (3 * b), 1e-14);  // the defining equation
    EXPECT_NEAR(s.f, row.f, 5e-7);                                           // the table's 7 digits
    EXPECT_NEAR(s.xx, row.Mxx, 5e-5 * row.Mxx);
    // the state satisfies the conformation equation with M_zz eliminated and as an unknown
    EXPECT_LT(shear_residual(FluidModel::FeneP, s, 1.0, row.W, b, false), 1e-12 * s.xx);
    EXPECT_LT(shear_residual(FluidModel::FeneP, s, 1.0, row.W, b, true), 1e-12 * s.xx);
    EXPECT_NEAR(s.zz, 1 / s.f, 1e-15);
    EXPECT_NEAR((s.xx + s.yy + s.zz) / 3, b - (b - 1) / s.f, 1e-12 * b);  // f = (b - 1)/(b - tr M / 3)
  }
}

TEST(ConstitutiveLaw, PlanarElongation) {
  for (double W : {0.1, 0.4}) {
    const SteadyConformation s = planar_elongation(FluidModel::OldroydB, W, 0.0);
    const double L[2][2] = {{1.0, 0.0}, {0.0, -1.0}};
    const Conformation<double> M{s.xx, s.xy, s.yy, 1.0};
    const Conformation<double> r = conformation_rate(M, L, 1.0, 1.0 / W);
    EXPECT_LT(std::max({std::abs(r.xx), std::abs(r.xy), std::abs(r.yy)}), 1e-12 * s.xx);
    EXPECT_NEAR(s.xx, 1 / (1 - 2 * W), 1e-15);
  }
  EXPECT_THROW(planar_elongation(FluidModel::OldroydB, 0.5, 0.0), std::domain_error);
  // FENE-P stays bounded beyond the Oldroyd-B singularity at W = 1/2. With the state's own f the
  // equations hold to rounding, and f satisfies its definition; recomputing f from M instead
  // would amplify rounding by 1/(f - 2W)^2 as tr M nears 3b.
  for (double W : {0.1, 0.5, 2.0, 10.0}) {
    const double b = 100;
    const SteadyConformation s = planar_elongation(FluidModel::FeneP, W, b);
    const double L[2][2] = {{1.0, 0.0}, {0.0, -1.0}};
    const Conformation<double> M{s.xx, s.xy, s.yy, s.zz};
    const Conformation<double> r = conformation_rate(M, L, s.f, 1.0 / W);
    EXPECT_LT(std::max({std::abs(r.xx), std::abs(r.yy), std::abs(r.zz)}), 1e-14 * (s.f / W + 2) * s.xx) << "W = " << W;
    // f is a root in double precision: one rounding of f moves the left side by about
    // f^2 (Mxx^2 + Myy^2 + Mzz^2) / 3 times the unit roundoff
    const double tol = 1e-13 * b + 10 * 2.2e-16 * s.f * s.f * (s.xx * s.xx + s.yy * s.yy + s.zz * s.zz) / 3;
    EXPECT_NEAR(s.f * (b - (s.xx + s.yy + s.zz) / 3), b - 1, tol) << "W = " << W;
    EXPECT_LT(s.xx + s.yy + s.zz, 3 * b);
  }
}

// Owens: locally Oldroyd-B with lambda_eff = lambda eta_p(gdot)/eta_p0; the steady shear viscosity
// is eta_s + eta_p(gdot) (dimensional: model units times eta0).
TEST(ConstitutiveLaw, OwensShearViscosityIsSolventPlusCross) {
  OwensParameters o;
  const double eta0 = o.eta_s + o.eta_p0, beta = o.beta(), Gamma = 4.95e-4, Wi = 1.3;
  for (double gdot_dim : {0.01, 1.0, 37.0, 1000.0}) {     // 1/s
    const double gdot = gdot_dim * Gamma / o.rate_scale;  // model units
    const double reg = std::sqrt(gdot_dim * gdot_dim + o.rate_floor * o.rate_floor);
    const double x = std::pow(reg, o.m);
    const double eta_p = o.eta_p0 * (1 + o.theta1() * x) / (1 + o.theta2 * x);
    // the law's factor and the state it gives
    const double factor = owens_factor(gdot * gdot, Gamma, o);
    EXPECT_NEAR(factor, eta_p / o.eta_p0, 1e-14);
    const double W = Wi / Gamma * factor * gdot;
    const SteadyConformation s = steady_shear(FluidModel::Owens, W, 0.0);
    EXPECT_LT(shear_residual(FluidModel::Owens, s, gdot, Wi / Gamma * factor, 0.0, false), 1e-12 * s.xx);
    // total shear stress / shear rate, in Pa s
    const double tau_xy = beta * gdot + (1 - beta) * Gamma / Wi * s.xy;
    EXPECT_NEAR(tau_xy / gdot * eta0, o.eta_s + eta_p, 1e-12 * eta0);
    EXPECT_NEAR(shear_viscosity(FluidModel::Owens, gdot, Wi, Gamma, beta, 0, o) * eta0, o.eta_s + eta_p, 1e-12 * eta0);
  }
  // Cross model limits: eta_p0 at rest (to the floor's 0.025%), eta_pinf at high shear
  EXPECT_NEAR(owens_factor(0.0, Gamma, o), 1.0, 3e-4);
  EXPECT_NEAR(owens_factor(std::pow(1e12 * Gamma / o.rate_scale, 2), Gamma, o), o.eta_pinf / o.eta_p0, 1e-6);
}

TEST(ConstitutiveLaw, LogFormHasTheSameSteadyStates) {
  for (FluidModel model : {FluidModel::OldroydB, FluidModel::FeneP}) {
    for (double W : {0.0, 0.5, 3.0}) {
      const double b = 50, gdot = 1.0;
      const SteadyConformation s = steady_shear(model, W, b);
      const Sym2<double> psi = sym_log({s.xx, s.xy, s.yy});
      const double L[2][2] = {{0.0, gdot}, {0.0, 0.0}};
      const double f = model == FluidModel::FeneP ? peterlin_eliminated(s.xx, s.yy, b) : 1.0;
      const double lambda = W / gdot;
      const Sym2<double> r = log_conformation_rate(psi, L, f, lambda > 0 ? 1 / lambda : 1e300);
      if (W == 0.0) continue;  // lambda = 0: the relaxation term alone, Psi = 0 satisfies it exactly
      EXPECT_LT(std::max({std::abs(r.xx), std::abs(r.xy), std::abs(r.yy)}), 1e-12 * s.xx)
          << to_string(model) << " W = " << W;
    }
  }
}
