// Constitutive laws against closed forms and independent solutions: steady simple shear and
// extension states make the pointwise conformation equation (the kernels' own) vanish, and
// stresses and viscosities are the known ones (Oldroyd-B, the FENE-P table of method.md, the Cross
// law of Owens) or the independent long-double solutions of support/HomogeneousReference.hpp
// (Giesekus, PTT, FENE-CR and all the others).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/LogConformation.hpp"
#include "problems/laws/SteadyFlows.hpp"
#include "support/HomogeneousReference.hpp"
#include "support/LawStates.hpp"

using namespace keller;

namespace {

// Residual of the steady homogeneous conformation equation at a closed-form state.
double shear_residual(FluidModel model, const SteadyConformation& s, double gdot, double lambda, double b,
                      bool dynamic) {
  const double L[2][2] = {{0.0, gdot}, {0.0, 0.0}};
  const Conformation<double> M{s.xx, s.xy, s.yy, s.zz};
  const Conformation<double> r =
      conformation_rate(M, L, relaxation(model, dynamic, M, LawConstants<double>{b}), 1.0 / lambda);
  return std::max({std::abs(r.xx), std::abs(r.xy), std::abs(r.yy), dynamic ? std::abs(r.zz) : 0.0});
}

}  // namespace

TEST(ConstitutiveLaw, OldroydBSimpleShear) {
  for (double W : {0.0, 0.3, 1.0, 7.5}) {
    const SteadyConformation s = steady_shear(FluidModel::OldroydB, W, {});
    EXPECT_EQ(s.xx, 1 + 2 * W * W);
    EXPECT_EQ(s.xy, W);
    EXPECT_EQ(s.yy, 1.0);
    EXPECT_LT(shear_residual(FluidModel::OldroydB, s, W, 1.0, 0.0, false), 1e-12 * s.xx);  // W = lambda gdot
    // polymer shear stress = (1 - beta) Gamma / Wi * W = (1 - beta) gdot: constant viscosity
    const double beta = 0.59, Gamma = 1.0, Wi = 0.7, gdot = W * Gamma / Wi;
    const Conformation<double> M{s.xx, s.xy, s.yy, 1.0};
    const Conformation<double> tp =
        polymer_stress(M, relaxation(FluidModel::OldroydB, false, M, LawConstants<double>{}), (1 - beta) * Gamma / Wi);
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
    const SteadyConformation s = steady_shear(FluidModel::FeneP, row.W, {b});
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
  const double L[2][2] = {{1.0, 0.0}, {0.0, -1.0}};
  const LawConstants<double> none;
  for (double W : {0.1, 0.4}) {
    const SteadyConformation s = steady_extension(FluidModel::OldroydB, Extension::Planar, W, none);
    const Conformation<double> M{s.xx, s.xy, s.yy, 1.0};
    const Conformation<double> r = conformation_rate(M, L, relaxation(FluidModel::OldroydB, false, M, none), 1.0 / W);
    EXPECT_LT(std::max({std::abs(r.xx), std::abs(r.xy), std::abs(r.yy)}), 1e-12 * s.xx);
    EXPECT_NEAR(s.xx, 1 / (1 - 2 * W), 1e-15);
  }
  EXPECT_THROW(steady_extension(FluidModel::OldroydB, Extension::Planar, 0.5, none), std::domain_error);
  // FENE-P stays bounded beyond the Oldroyd-B singularity at W = 1/2. With the state's own f the
  // equations hold to rounding, and f satisfies its definition; recomputing f from M instead
  // would amplify rounding by 1/(f - 2W)^2 as tr M nears 3b.
  for (double W : {0.1, 0.5, 2.0, 10.0}) {
    const double b = 100;
    const SteadyConformation s = steady_extension(FluidModel::FeneP, Extension::Planar, W, {b});
    const Conformation<double> M{s.xx, s.xy, s.yy, s.zz};
    const Relaxation<double> k{-1.0, s.f, 0.0, -1.0, s.f, s.f};
    const Conformation<double> r = conformation_rate(M, L, k, 1.0 / W);
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
    const SteadyConformation s = steady_shear(FluidModel::Owens, W, {});
    EXPECT_LT(shear_residual(FluidModel::Owens, s, gdot, Wi / Gamma * factor, 0.0, false), 1e-12 * s.xx);
    // total shear stress / shear rate, in Pa s
    const double tau_xy = beta * gdot + (1 - beta) * Gamma / Wi * s.xy;
    EXPECT_NEAR(tau_xy / gdot * eta0, o.eta_s + eta_p, 1e-12 * eta0);
    EXPECT_NEAR(shear_viscosity(FluidModel::Owens, gdot, Wi, Gamma, beta, {}, o) * eta0, o.eta_s + eta_p, 1e-12 * eta0);
  }
  // Cross model limits: eta_p0 at rest (to the floor's 0.025%), eta_pinf at high shear
  EXPECT_NEAR(owens_factor(0.0, Gamma, o), 1.0, 3e-4);
  EXPECT_NEAR(owens_factor(std::pow(1e12 * Gamma / o.rate_scale, 2), Gamma, o), o.eta_pinf / o.eta_p0, 1e-6);
}

namespace {

// The laws and constants the tests below sweep: each shipped law, the new ones at the ends and
// the middle of their ranges.
struct LawCase {
  FluidModel model;
  LawConstants<double> c;
};
std::vector<LawCase> law_cases() {
  std::vector<LawCase> v = {{FluidModel::OldroydB, {}},
                            {FluidModel::FeneP, {5.0}},
                            {FluidModel::FeneP, {100.0}},
                            {FluidModel::FeneCr, {3.0}},
                            {FluidModel::FeneCr, {100.0}}};
  for (double a : {0.0, 0.01, 0.3, 0.5}) v.push_back({FluidModel::Giesekus, {100.0, a}});
  for (FluidModel m : {FluidModel::PttLinear, FluidModel::PttExponential})
    for (double e : {0.0, 0.02, 0.25})
      for (double xi : {0.0, 0.1, 0.5}) v.push_back({m, {100.0, 0.0, e, xi}});
  return v;
}

std::string describe(const LawCase& l) {
  return std::string(to_string(l.model)) + " b " + std::to_string(l.c.b) + " alpha " + std::to_string(l.c.alpha) +
         " epsilon " + std::to_string(l.c.epsilon) + " xi " + std::to_string(l.c.xi);
}

test::ReferenceLaw reference(const LawCase& l) { return {l.model, l.c.b, l.c.alpha, l.c.epsilon, l.c.xi}; }

// The largest deviation of t from the reference r, relative to the larger of 1 and |r|.
double deviation(const Conformation<double>& t, const test::Tensor& r) {
  double scale = 1, worst = 0;
  for (long double x : r) scale = std::max(scale, static_cast<double>(std::abs(x)));
  const double got[4] = {t.xx, t.xy, t.yy, t.zz};
  for (int i = 0; i < 4; ++i) worst = std::max(worst, std::abs(got[i] - static_cast<double>(r[i])));
  return worst / scale;
}

// The law's pointwise rate (the kernels' conformation_rate) at a state, relative to its terms.
double rate_residual(const LawCase& l, const SteadyConformation& s, const double (&L)[2][2], double Lzz) {
  const Conformation<double> M{s.xx, s.xy, s.yy, s.zz};
  const double* xi = is_ptt(l.model) ? &l.c.xi : nullptr;
  const Conformation<double> r = conformation_rate(M, L, test::terms_at(l.model, l.c, s), 1.0, xi, Lzz);
  const double scale =
      std::max({1.0, std::abs(s.xx), std::abs(s.yy), std::abs(s.zz)}) * (1 + std::abs(L[0][0]) + std::abs(L[0][1]));
  return std::max({std::abs(r.xx), std::abs(r.xy), std::abs(r.yy), std::abs(r.zz)}) / scale;
}

}  // namespace

// Every law's steady shear state (SteadyFlows.cpp: closed forms, PTT's scalar root) against the
// independent long-double solution, W = lambda gdot from 1e-3 to 1e3: the stress to 1e-12 of its
// size (the closed forms are a few roundings deep; the reference is exact to 1e-17), the kernels'
// rate zero there to 1e-12, and polymer_shear_ratio = t_xy / W to 1e-12.
TEST(ConstitutiveLaw, EveryLawsShearStateIsTheIndependentSolution) {
  for (const LawCase& l : law_cases()) {
    double worst = 0;
    for (double W : {1e-3, 0.1, 1.0, 3.0, 10.0, 100.0, 1000.0}) {
      const SteadyConformation s = steady_shear(l.model, W, l.c);
      const test::Tensor ref = test::reference_state(reference(l), test::shear_gradient(), W);
      const double d = deviation(test::closed_stress(l.model, l.c, s), ref);
      EXPECT_LT(d, 1e-12) << describe(l) << " W = " << W;
      worst = std::max(worst, d);
      const double L[2][2] = {{0.0, W}, {0.0, 0.0}};
      EXPECT_LT(rate_residual(l, s, L, 0.0), 1e-12) << describe(l) << " W = " << W;
      const double ratio = polymer_shear_ratio(l.model, W, l.c), expected = static_cast<double>(ref[1]) / W;
      EXPECT_NEAR(ratio, expected, 1e-12 * expected) << describe(l) << " W = " << W;
    }
    std::printf("%s: shear state within %.1e of the reference\n", describe(l).c_str(), worst);
  }
}

// The same for planar and uniaxial extension at W = lambda eps up to 200, where the law has a
// steady state; where it has none (Oldroyd-B, Giesekus alpha = 0 and PTT epsilon = 0 at
// 2 (1 - xi) W >= 1) steady_extension says so. Uniaxial extension's y and z are the same state.
TEST(ConstitutiveLaw, EveryLawsExtensionStateIsTheIndependentSolution) {
  for (const LawCase& l : law_cases())
    for (Extension kind : {Extension::Planar, Extension::Uniaxial}) {
      const bool bounded =
          uses_b(l.model) || (l.model == FluidModel::Giesekus && l.c.alpha > 0) || (is_ptt(l.model) && l.c.epsilon > 0);
      const double limit = is_ptt(l.model) ? 0.5 / (1 - l.c.xi) : 0.5;
      for (double W : {0.01, 0.2, 0.45, 0.7, 2.0, 20.0, 200.0}) {
        if (!bounded && W >= limit) {
          EXPECT_THROW(steady_extension(l.model, kind, W, l.c), std::domain_error) << describe(l) << " W = " << W;
          continue;
        }
        const SteadyConformation s = steady_extension(l.model, kind, W, l.c);
        const test::Gradient G = kind == Extension::Planar ? test::planar_gradient() : test::uniaxial_gradient();
        test::Tensor ref{};
        try {
          ref = test::reference_state(reference(l), G, W);
        } catch (const std::exception& e) {
          ADD_FAILURE() << e.what() << ": " << describe(l) << " " << to_string(kind) << " W = " << W;
          continue;
        }
        EXPECT_LT(deviation(test::closed_stress(l.model, l.c, s), ref), 1e-11)
            << describe(l) << " " << to_string(kind) << " W = " << W;
        const double L[2][2] = {{W, 0.0}, {0.0, kind == Extension::Planar ? -W : -0.5 * W}};
        EXPECT_LT(rate_residual(l, s, L, kind == Extension::Planar ? 0.0 : -0.5 * W), 1e-12)
            << describe(l) << " " << to_string(kind) << " W = " << W;
        if (kind == Extension::Uniaxial) {
          EXPECT_NEAR(s.yy, s.zz, 1e-14 * s.yy) << describe(l);
        }
      }
    }
}

// At rest every law's relaxation vanishes, P(I) = 0, and so does its stress: M = I is the rest state.
TEST(ConstitutiveLaw, TheRestStateIsRelaxed) {
  const Conformation<double> I{1.0, 0.0, 1.0, 1.0};
  for (const LawCase& l : law_cases()) {
    const Relaxation<double> k = relaxation(l.model, true, I, l.c);
    const Conformation<double> p = relaxation_tensor(I, k), t = polymer_stress(I, k, 1.0);
    EXPECT_EQ(k.factor, 1.0) << describe(l);
    for (double x : {p.xx, p.xy, p.yy, p.zz, t.xx, t.xy, t.yy, t.zz}) EXPECT_NEAR(x, 0.0, 1e-15) << describe(l);
  }
}

// The log form has the same steady states: its rate at Psi = log M of every law's shear and
// extension states vanishes (xi = 0, the log form's only slip).
TEST(ConstitutiveLaw, LogFormHasTheSameSteadyStates) {
  for (const LawCase& l : law_cases()) {
    if (l.c.xi != 0.0) continue;
    for (double W : {0.5, 3.0, 30.0}) {
      for (int flow = 0; flow < 3; ++flow) {
        const bool bounded = uses_b(l.model) || (l.model == FluidModel::Giesekus && l.c.alpha > 0) ||
                             (is_ptt(l.model) && l.c.epsilon > 0);
        if (flow > 0 && !bounded && W >= 0.5) continue;
        const SteadyConformation s =
            flow == 0 ? steady_shear(l.model, W, l.c)
                      : steady_extension(l.model, flow == 1 ? Extension::Planar : Extension::Uniaxial, W, l.c);
        const double L[2][2] = {{flow == 0 ? 0.0 : W, flow == 0 ? W : 0.0},
                                {0.0, flow == 0 ? 0.0 : (flow == 1 ? -W : -0.5 * W)}};
        const double Lzz = flow == 2 ? -0.5 * W : 0.0;
        const Sym2<double> psi = sym_log({s.xx, s.xy, s.yy});
        const Sym2<double> M{s.xx, s.xy, s.yy};
        const Relaxation<double> k = test::terms_at(l.model, l.c, s);
        const Sym2<double> r = log_conformation_rate(psi, L, k, M, 1.0);
        const double rz = log_conformation_rate_zz(std::log(s.zz), k, s.zz, 1.0, Lzz);
        // the log form's terms are O(1 + W |log M|); its rounding is that times a few eps
        const double scale = 1 + W * std::max({1.0, std::abs(psi.xx), std::abs(psi.yy)});
        EXPECT_LT(std::max({std::abs(r.xx), std::abs(r.xy), std::abs(r.yy), std::abs(rz)}), 1e-12 * scale)
            << describe(l) << " flow " << flow << " W = " << W;
      }
    }
  }
}
