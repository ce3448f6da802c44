// Steady-shear viscosity of each viscoelastic law in both formulations, computed from the
// formulation's own pointwise equations, against closed forms. The state of steady homogeneous
// simple shear, L = [[0, gdot], [0, 0]] and v . grad M = 0, is RheometryProblem's: the kernels'
// pointwise residual (conformation_rate, or log_conformation_rate with M = exp(Psi), as
// ViscoelasticFlowKernel evaluates them) with dual-number Jacobians, solved here by Newton and
// continued in the rate from rest; its observable eta = eta_s + eta_p (model units, eta0 = 1) is
// compared with
//   Owens: eta_s + eta_p0 (1 + theta1 r^m) / (1 + theta2 r^m) (the Cross law) at dimensional
//     shear rates r from 1e-3 to 1e4 1/s, r regularised by the law's floor as the law defines;
//     and the unregularised Cross law within the floor's analytic effect;
//   FENE-P: beta + (1 - beta) / f with f the real root of f^2 (f - 1) = 2 W^2 / (3 b),
//     W = lambda gdot, by Cardano's formula, for b = 2 to 100 and W = 1e-3 to 1e3, with M_zz
//     eliminated and as an unknown;
//   Oldroyd-B: 1.
// Tolerance 1e-10 relative: Newton ends one quadratically convergent step after an update of
// 1e-12 relative, which leaves the state exact to rounding, and the viscosity's sensitivity to
// rounding in the state is at most about 3b / (3b - tr M) <= 1e3 here.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "problems/laws/SteadyFlows.hpp"
#include "problems/rheometry/RheometryProblem.hpp"
#include "support/LawStates.hpp"
#include "support/ShearClosedForms.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

RheometryOptions law(FluidModel model, bool log_form, bool dynamic_zz, double Gamma, double Wi, double beta, double b) {
  RheometryOptions o;
  o.law.model = model;
  o.law.log_conformation = log_form;
  o.law.dynamic_zz = dynamic_zz;
  o.law.constants.b = b;
  o.Gamma = Gamma;
  o.Wi = Wi;
  o.beta = beta;
  return o;
}

std::string describe(const RheometryOptions& o) {
  return std::string(to_string(o.law.model)) + (o.law.log_conformation ? " log" : " conf") +
         (o.law.dynamic_zz ? " zz" : "") + ", b = " + std::to_string(o.law.constants.b);
}

// Newton on the problem at its current rate from u; returns false without convergence.
bool solve(RheometryProblem& p, Vector& u) {
  Vector F;
  SparseMatrix J;
  for (int it = 0; it < 60; ++it) {
    if (!p.jacobian(u, F, J).is_ok()) return false;
    const Vector du = Eigen::MatrixXd(J).partialPivLu().solve(-F);
    if (!du.allFinite()) return false;
    u += du;
    // Newton converges quadratically: a step of 1e-12 leaves an error of rounding size
    if (du.cwiseAbs().maxCoeff() <= 1e-12 * std::max(u.cwiseAbs().maxCoeff(), 1.0)) return true;
  }
  return false;
}

// Viscosity eta / eta0 of the steady shear state at each rate (1/s), continued from rest in
// increasing rate.
std::vector<double> viscosities(const RheometryOptions& o, const std::vector<double>& rates) {
  RheometryProblem p(o);
  Vector u = p.initial_guess();
  const std::vector<std::string> names = p.observable_names();
  const auto eta_at = std::find(names.begin(), names.end(), "eta") - names.begin();
  std::vector<double> eta;
  for (double r : rates) {
    p.parameters().set("log10_rate", std::log10(r));
    EXPECT_TRUE(solve(p, u)) << "no steady shear state at r = " << r << " (" << describe(o) << ")";
    std::vector<double> obs;
    EXPECT_TRUE(p.observables(u, obs).is_ok());
    eta.push_back(obs[static_cast<size_t>(eta_at)]);
  }
  return eta;
}

std::vector<double> logspace(double a, double b, int n) {
  std::vector<double> x;
  for (int k = 0; k < n; ++k) x.push_back(a * std::pow(b / a, k / double(n - 1)));
  return x;
}

}  // namespace

TEST(Rheometry, CardanoRootSolvesTheCubic) {
  for (double c : {0.0, 1e-8, 0.01, 1.0, 1e6}) {
    const double f = test::peterlin_cardano(c);
    EXPECT_NEAR(f * f * (f - 1), c, 1e-14 * std::max(1.0, c) * f * f) << c;
  }
}

TEST(Rheometry, OwensIsTheCrossLaw) {
  const OwensParameters o;
  const double eta0 = o.eta_s + o.eta_p0;
  for (bool log_form : {false, true}) {
    const RheometryOptions l = law(FluidModel::Owens, log_form, false, 4.95e-4, 1.0, o.beta(), 100.0);
    const std::vector<double> rates = logspace(1e-3, 1e4, 29);  // 1/s
    const std::vector<double> eta = viscosities(l, rates);
    double worst = 0;
    for (size_t k = 0; k < rates.size(); ++k) {
      const double r = rates[k];
      const double regularised = test::cross_viscosity(o, std::hypot(r, o.rate_floor));
      EXPECT_NEAR(eta[k] * eta0, regularised, 1e-10 * regularised) << (log_form ? "log" : "conf") << " r = " << r;
      worst = std::max(worst, std::abs(eta[k] * eta0 / regularised - 1));
      // The floor changes ln r by ln(1 + (floor/r)^2)/2 <= (floor/r)^2 / 2, and
      // |d ln eta / d ln r| <= m, so the relative change is at most m (floor/r)^2 / 2.
      const double bound = o.m * 0.5 * std::pow(o.rate_floor / r, 2), cross = test::cross_viscosity(o, r);
      EXPECT_NEAR(eta[k] * eta0, cross, (bound + 1e-10) * cross) << "r = " << r;
    }
    std::printf("Owens %s: largest relative deviation from the Cross law %.1e\n", log_form ? "log" : "conf", worst);
    // the range spans the law: from near eta_s + eta_p0 down to near eta_s + eta_pinf
    EXPECT_GT(eta.front() * eta0, 0.95 * eta0);
    EXPECT_LT(eta.back() * eta0, 1.1 * (o.eta_s + o.eta_pinf));
  }
}

TEST(Rheometry, FenePIsTheClosedForm) {
  for (bool log_form : {false, true})
    for (bool dynamic : {false, true})
      for (double b : {2.0, 5.0, 20.0, 100.0}) {
        // Wi = 0.5: lambda_0 = 5 ms, W = lambda_0 r, so r = 200 W (1/s)
        const RheometryOptions l = law(FluidModel::FeneP, log_form, dynamic, 1.0, 0.5, 0.2, b);
        const std::vector<double> W = logspace(1e-3, 1e3, 25);
        std::vector<double> rates;
        for (double w : W) rates.push_back(w * 200.0);
        const std::vector<double> eta = viscosities(l, rates);
        double worst = 0;
        for (size_t k = 0; k < W.size(); ++k) {
          const double closed = l.beta + (1 - l.beta) * test::fene_p_viscosity_ratio(W[k], b);
          EXPECT_NEAR(eta[k], closed, 1e-10 * closed) << describe(l) << " W = " << W[k];
          worst = std::max(worst, std::abs(eta[k] / closed - 1));
        }
        std::printf("%s: largest relative deviation from the closed form %.1e\n", describe(l).c_str(), worst);
      }
}

// Oldroyd-B's viscosity is constant, eta = eta0 at every rate, to rounding: the shear stress is
// O(W) (W = lambda_0 r, 1e-3 to 100 here) while the conformation's entries are O(1 + 2 W^2) (M_xx),
// and the log-conformation form computes the stress from exp(Psi) of that size, so its relative
// rounding error is about eps (1 + 2 W^2) / W times a constant of the eigen-decomposition; the
// constant measured at W = 100 in the log form is 6 in the optimised build and 30 in the
// sanitizers' -O1 build (1.3e-12): 64 is asked.
TEST(Rheometry, OldroydBHasConstantViscosity) {
  for (bool log_form : {false, true}) {
    const RheometryOptions l = law(FluidModel::OldroydB, log_form, false, 1.0, 0.5, 0.3, 100.0);
    const std::vector<double> rates = logspace(0.2, 2e4, 11);
    const std::vector<double> eta = viscosities(l, rates);
    for (size_t k = 0; k < rates.size(); ++k) {
      const double W = rates[k] / 200.0;  // lambda_0 = 5 ms at Wi = 0.5, as above
      const double eps = std::numeric_limits<double>::epsilon();
      EXPECT_NEAR(eta[k], 1.0, 64 * eps * (1 + 2 * W * W) / W) << (log_form ? "log" : "conf") << " W = " << W;
    }
  }
}

// The exact Jacobian against central differences at a sheared state of every law and form; and
// the scaling F = lambda R: at rest J = I (Oldroyd-B) and B = lambda I, so the relaxation rate
// is 1/lambda.
TEST(Rheometry, JacobianAndRelaxation) {
  for (FluidModel m : {FluidModel::OldroydB, FluidModel::FeneP, FluidModel::Owens})
    for (bool log_form : {false, true})
      for (bool dynamic : {false, true}) {
        if (dynamic && m != FluidModel::FeneP) continue;
        const RheometryOptions l = law(m, log_form, dynamic, 4.95e-4, 0.5, 0.2, 5.0);
        RheometryProblem p(l);
        Vector u = p.initial_guess();
        p.parameters().set("log10_rate", 2.0);  // W = lambda_0 r = 0.5
        ASSERT_TRUE(solve(p, u)) << describe(l);
        u += Vector::Constant(u.size(), 0.01);  // off the solution, where F != 0
        const test::JacobianCheck c = test::check_problem_jacobian(p, u);
        EXPECT_LT(c.max_relative_error, 1e-7) << describe(l) << " row " << c.worst_row << " col " << c.worst_col;
        p.parameters().set("log10_rate", -30.0);
        Vector F;
        SparseMatrix J, B;
        const Vector rest = p.initial_guess();
        ASSERT_TRUE(p.jacobian(rest, F, J).is_ok());
        ASSERT_TRUE(p.mass_matrix(rest, B).is_ok());
        EXPECT_LT(F.cwiseAbs().maxCoeff(), 1e-15) << describe(l);
        const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(p.size(), p.size());
        // (FENE-P's f and Owens' relaxation factor add their own derivatives at rest)
        if (m == FluidModel::OldroydB) {
          EXPECT_LT((Eigen::MatrixXd(J) - I).norm(), 1e-12) << describe(l);
        }
        EXPECT_LT((Eigen::MatrixXd(B) - (l.Wi / l.Gamma) * I).norm(), 1e-12 * l.Wi / l.Gamma) << describe(l);
      }
}

namespace {

// The laws added after the reference study's four, at one set of constants each (the closed
// forms are checked over their whole ranges in ConstitutiveLawTest).
struct LawCase {
  FluidModel model;
  LawConstants<double> c;
};
const LawCase kNewLaws[] = {{FluidModel::Giesekus, {100.0, 0.3}},
                            {FluidModel::PttLinear, {100.0, 0.0, 0.25}},
                            {FluidModel::PttLinear, {100.0, 0.0, 0.25, 0.1}},
                            {FluidModel::PttExponential, {100.0, 0.0, 0.02}},
                            {FluidModel::FeneCr, {10.0}}};

RheometryOptions options(const LawCase& l, HomogeneousFlow flow, bool log_form) {
  RheometryOptions o;
  o.flow = flow;
  o.law.model = l.model;
  o.law.log_conformation = log_form;
  o.law.constants = l.c;
  o.Gamma = 1.0;
  o.Wi = 0.5;  // lambda_0 = Wi / rate_scale = 5 ms: W = lambda_0 r
  o.beta = 0.2;
  return o;
}

std::string describe(const LawCase& l, HomogeneousFlow flow, bool log_form) {
  return std::string(problem_type(flow)) + " " + to_string(l.model) + (log_form ? " log" : " conf") + " alpha " +
         std::to_string(l.c.alpha) + " epsilon " + std::to_string(l.c.epsilon) + " xi " + std::to_string(l.c.xi);
}

// Continues p's state u in log10_rate from `done` to `target` (lambda_0 r = W): a step that
// Newton cannot take, or that lands on a root that is no state of the law (refused by the
// problem), is halved.
void advance(RheometryProblem& p, Vector& u, double& done, double target, const std::string& what) {
  for (double step = target - done; done < target;) {
    const double next = std::min(target, done + step);
    p.parameters().set("log10_rate", next);
    Vector v = u;
    if (solve(p, v)) {
      u = v;
      done = next;
    } else {
      step *= 0.5;
      ASSERT_GT(step, 1e-6) << what << " stalled at log10 rate " << done;
    }
  }
}

}  // namespace

// Every new law in shear, planar and uniaxial extension and both forms (xi > 0 has only the
// conformation form), continued from rest over W = lambda_0 r = 1e-3 to 1e3, against SteadyFlows'
// closed forms: the polymer viscosity eta_p / eta_p0, the first normal stress coefficient
// psi1_p = N1_p / (2 eta_p0 lambda gdot^2) and the extensional viscosity eta_e_p = (tau_xx -
// tau_yy)_p / (eta_p0 eps), to 1e-10 relative. Newton ends a quadratically convergent step after
// an update of 1e-12 relative, which leaves the state exact to rounding; the observables'
// sensitivity to it is at most the conformation's size over the stress's, below 1e3 here.
TEST(Rheometry, EveryLawFollowsItsClosedFormsInShearAndExtension) {
  for (const LawCase& l : kNewLaws)
    for (HomogeneousFlow flow :
         {HomogeneousFlow::Shear, HomogeneousFlow::PlanarExtension, HomogeneousFlow::UniaxialExtension})
      for (bool log_form : {false, true}) {
        if (log_form && l.c.xi != 0.0) continue;
        const RheometryOptions o = options(l, flow, log_form);
        RheometryProblem p(o);
        Vector u = p.initial_guess();
        const std::vector<std::string> names = p.observable_names();
        auto at = [&](const char* n) {
          return static_cast<size_t>(std::find(names.begin(), names.end(), n) - names.begin());
        };
        double worst = 0;
        double done = std::log10(1e-3 / 0.005) - 0.25;
        for (double W : logspace(1e-3, 1e3, 25)) {
          advance(p, u, done, std::log10(W / 0.005), describe(l, flow, log_form));
          if (testing::Test::HasFatalFailure()) return;
          std::vector<double> obs;
          ASSERT_TRUE(p.observables(u, obs).is_ok());
          EXPECT_NEAR(obs[at("Wi_local")], W, 1e-13 * W);
          auto check = [&](double got, double expected, const char* what, double rounding = 0.0) {
            EXPECT_NEAR(got, expected, (1e-10 + rounding) * std::abs(expected))
                << describe(l, flow, log_form) << " W = " << W << " " << what;
            worst = std::max(worst, std::abs(got / expected - 1));
          };
          if (flow == HomogeneousFlow::Shear) {
            const Conformation<double> t = test::closed_stress(l.model, l.c, steady_shear(l.model, W, l.c));
            check(obs[at("eta_p")], polymer_shear_ratio(l.model, W, l.c), "eta_p");
            // N1 = M_xx - M_yy of entries of size 1 + O(W^2): their rounding (measured: half an eps in
            // the log form) is eps / (2 W^2) of N1 at small W, 5e-11 at W = 1e-3; 8 eps are allowed
            const double eps = std::numeric_limits<double>::epsilon();
            check(obs[at("psi1_p")], (t.xx - t.yy) / (2 * W * W), "psi1_p", 8 * eps / (2 * W * W));
          } else {
            const Extension kind = flow == HomogeneousFlow::PlanarExtension ? Extension::Planar : Extension::Uniaxial;
            const Conformation<double> t = test::closed_stress(l.model, l.c, steady_extension(l.model, kind, W, l.c));
            check(obs[at("eta_e_p")], (t.xx - t.yy) / W, "eta_e_p");
            // the solvent adds 4 beta (planar) or 3 beta (uniaxial): the Trouton ratio at low rate
            const double trouton = kind == Extension::Planar ? 4.0 : 3.0;
            EXPECT_NEAR(obs[at("eta_e")], o.beta * trouton + (1 - o.beta) * obs[at("eta_e_p")],
                        1e-12 * obs[at("eta_e")]);
            if (W == 1e-3) {
              EXPECT_NEAR(obs[at("eta_e")], trouton, 1e-2 * trouton);
            }
          }
        }
        std::printf("%s: largest relative deviation from the closed forms %.1e\n", describe(l, flow, log_form).c_str(),
                    worst);
      }
}

// The exact Jacobian of every new law in every flow and form against central differences, off
// the solution at W = 0.3.
TEST(Rheometry, EveryLawsJacobianIsExact) {
  for (const LawCase& l : kNewLaws)
    for (HomogeneousFlow flow :
         {HomogeneousFlow::Shear, HomogeneousFlow::PlanarExtension, HomogeneousFlow::UniaxialExtension})
      for (bool log_form : {false, true}) {
        if (log_form && l.c.xi != 0.0) continue;
        RheometryProblem p(options(l, flow, log_form));
        Vector u = p.initial_guess();
        p.parameters().set("log10_rate", std::log10(0.3 / 0.005));
        ASSERT_TRUE(solve(p, u)) << describe(l, flow, log_form);
        u += Vector::Constant(u.size(), 0.01);
        const test::JacobianCheck c = test::check_problem_jacobian(p, u);
        EXPECT_LT(c.max_relative_error, 1e-7) << describe(l, flow, log_form) << " row " << c.worst_row;
      }
}

// A three-mode fluid (times 1, 0.1 and 0.01 lambda; shares 0.5, 0.3, 0.2) of each new law, in
// every flow and form: each observable is the sum of its modes' closed forms, mode k at its own
// W_k = t_k W with weight w_k (eta_p and eta_e_p) or w_k t_k (psi1_p: its N1 over the reference
// lambda), to the same 1e-10 as one mode, over W = 1e-2 to 1e3.
TEST(Rheometry, AMultiModeLawIsTheSumOfItsModes) {
  const double times[] = {1.0, 0.1, 0.01}, shares[] = {0.5, 0.3, 0.2};
  const char* const kModeNames[] = {"m0", "m1", "m2"};
  for (const LawCase& l : kNewLaws)
    for (HomogeneousFlow flow :
         {HomogeneousFlow::Shear, HomogeneousFlow::PlanarExtension, HomogeneousFlow::UniaxialExtension})
      for (bool log_form : {false, true}) {
        if (log_form && l.c.xi != 0.0) continue;
        RheometryOptions o = options(l, flow, log_form);
        for (int k = 0; k < 3; ++k) o.law.modes.push_back({kModeNames[k], times[k], shares[k]});
        RheometryProblem p(o);
        ASSERT_EQ(p.size(), 3 * (flow == HomogeneousFlow::Shear ? 3 : 4));
        Vector u = p.initial_guess();
        const std::vector<std::string> names = p.observable_names();
        auto at = [&](const char* n) {
          return static_cast<size_t>(std::find(names.begin(), names.end(), n) - names.begin());
        };
        double done = std::log10(1e-2 / 0.005) - 0.25;
        for (double W : logspace(1e-2, 1e3, 11)) {
          advance(p, u, done, std::log10(W / 0.005), describe(l, flow, log_form) + " three modes");
          if (testing::Test::HasFatalFailure()) return;
          std::vector<double> obs;
          ASSERT_TRUE(p.observables(u, obs).is_ok());
          // N1 = M_xx - M_yy of mode k has eps / (2 W_k^2) of its psi1 in rounding (8 eps allowed, as above)
          const double eps = std::numeric_limits<double>::epsilon();
          double eta_p = 0, psi1_p = 0, eta_e_p = 0, rounding = 0;
          for (int k = 0; k < 3; ++k) {
            const double Wk = times[k] * W;
            if (flow == HomogeneousFlow::Shear) {
              const Conformation<double> t = test::closed_stress(l.model, l.c, steady_shear(l.model, Wk, l.c));
              eta_p += shares[k] * polymer_shear_ratio(l.model, Wk, l.c);
              psi1_p += shares[k] * times[k] * (t.xx - t.yy) / (2 * Wk * Wk);
              rounding += shares[k] * times[k] * 8 * eps / (2 * Wk * Wk);
            } else {
              const Extension kind = flow == HomogeneousFlow::PlanarExtension ? Extension::Planar : Extension::Uniaxial;
              const Conformation<double> t =
                  test::closed_stress(l.model, l.c, steady_extension(l.model, kind, Wk, l.c));
              eta_e_p += shares[k] * (t.xx - t.yy) / Wk;
            }
          }
          const std::string what = describe(l, flow, log_form) + " three modes, W = " + std::to_string(W);
          if (flow == HomogeneousFlow::Shear) {
            EXPECT_NEAR(obs[at("eta_p")], eta_p, 1e-10 * eta_p) << what;
            EXPECT_NEAR(obs[at("psi1_p")], psi1_p, 1e-10 * psi1_p + rounding) << what;
          } else {
            EXPECT_NEAR(obs[at("eta_e_p")], eta_e_p, 1e-10 * eta_e_p) << what;
          }
        }
      }
}
