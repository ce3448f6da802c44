// Steady-shear viscosity of each viscoelastic law in both formulations, computed from the
// formulation's own pointwise equations, against closed forms. The state of steady homogeneous
// simple shear, L = [[0, gdot], [0, 0]] and v . grad M = 0, solves the kernels' pointwise
// residual (conformation_rate, or log_conformation_rate with M = exp(Psi), as
// ViscoelasticFlowKernel evaluates them) by Newton with dual-number Jacobians, continued in
// gdot from rest; the viscosity eta_s + eta_p = beta + tau_p,xy / gdot (model units, eta0 = 1)
// is then compared with
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
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/AutoDiff.hpp"
#include "problems/kernels/ViscoelasticFlowKernel.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/LogConformation.hpp"

using namespace keller;

namespace {

struct Law {
  FluidModel model;
  bool log_form;
  bool dynamic_zz;
  double Gamma, Wi, beta, b;
  OwensParameters owens;
  int size() const { return dynamic_zz ? 4 : 3; }
};

// The pointwise steady residual of the formulation at unknowns u (M or Psi components).
template <int NC, class T>
void residual(const Law& law, double gdot, const T* u, T* r) {
  const double L[2][2] = {{0.0, gdot}, {0.0, 0.0}};
  const Conformation<T> M = conformation_of<NC>(u, law.log_form);
  const T f = peterlin(law.model, NC == 4, M, law.b);
  double inv_lambda = law.Gamma / law.Wi;
  if (law.model == FluidModel::Owens) inv_lambda /= owens_factor(gdot * gdot, law.Gamma, law.owens);  // 2 D:D = gdot^2
  if (law.log_form) {
    using std::exp;
    const Sym2<T> rate = log_conformation_rate(Sym2<T>{u[0], u[1], u[2]}, L, f, inv_lambda);
    r[0] = rate.xx;
    r[1] = rate.xy;
    r[2] = rate.yy;
    if constexpr (NC == 4) r[3] = -inv_lambda * (exp(-u[3]) - f);
  } else {
    const Conformation<T> rate = conformation_rate(M, L, f, inv_lambda);
    r[0] = rate.xx;
    r[1] = rate.xy;
    r[2] = rate.yy;
    if constexpr (NC == 4) r[3] = rate.zz;
  }
}

// Newton on the pointwise residual from u; returns false without convergence.
template <int NC>
bool solve(const Law& law, double gdot, std::array<double, 4>& u) {
  using D = Dual<NC>;
  for (int it = 0; it < 60; ++it) {
    D ud[NC], rd[NC];
    for (int i = 0; i < NC; ++i) ud[i] = make_variable<NC>(u[i], i);
    residual<NC>(law, gdot, ud, rd);
    Eigen::Matrix<double, NC, NC> J;
    Eigen::Matrix<double, NC, 1> F;
    for (int i = 0; i < NC; ++i) {
      F[i] = rd[i].value();
      J.row(i) = rd[i].derivatives().transpose();
    }
    const Eigen::Matrix<double, NC, 1> du = J.partialPivLu().solve(-F);
    double unorm = 0;
    for (int i = 0; i < NC; ++i) {
      u[i] += du[i];
      unorm = std::max(unorm, std::abs(u[i]));
    }
    if (!du.allFinite()) return false;
    // Newton converges quadratically: a step of 1e-12 leaves an error of rounding size
    if (du.cwiseAbs().maxCoeff() <= 1e-12 * std::max(unorm, 1.0)) return true;
  }
  return false;
}

// Viscosity eta / eta0 of the steady shear state at each shear rate (model units), continued
// from rest in increasing gdot.
std::vector<double> viscosities(const Law& law, const std::vector<double>& gdots) {
  std::array<double, 4> u = law.log_form ? std::array<double, 4>{0, 0, 0, 0} : std::array<double, 4>{1, 0, 1, 1};
  std::vector<double> eta;
  for (double g : gdots) {
    const bool ok = law.size() == 4 ? solve<4>(law, g, u) : solve<3>(law, g, u);
    EXPECT_TRUE(ok) << "no steady shear state at gdot = " << g << " (" << to_string(law.model)
                    << (law.log_form ? " log" : " conf") << (law.dynamic_zz ? " zz" : "") << ", b = " << law.b << ")";
    const Conformation<double> M =
        law.size() == 4 ? conformation_of<4>(u.data(), law.log_form) : conformation_of<3>(u.data(), law.log_form);
    const double f = peterlin(law.model, law.dynamic_zz, M, law.b);
    const Conformation<double> tp = polymer_stress(M, f, (1 - law.beta) * law.Gamma / law.Wi);
    eta.push_back(law.beta + tp.xy / g);
  }
  return eta;
}

// The real root of f^2 (f - 1) = c (c >= 0) by Cardano: with f = y + 1/3, y^3 + p y + q = 0,
// p = -1/3, q = -(2/27 + c), whose discriminant (q/2)^2 + (p/3)^3 = c/27 + c^2/4 is positive:
// y = A + B, A = cbrt(h + s), B = cbrt(h - s), h = -q/2, s = sqrt(discriminant). Since
// A B = -p/3 = 1/9, B = 1/(9 A), which avoids the cancellation in h - s at large c.
double peterlin_cardano(double c) {
  const double h = 1.0 / 27.0 + 0.5 * c, s = std::sqrt(c / 27.0 + 0.25 * c * c);
  const double A = std::cbrt(h + s);
  return 1.0 / 3.0 + A + 1.0 / (9.0 * A);
}

std::vector<double> logspace(double a, double b, int n) {
  std::vector<double> x;
  for (int k = 0; k < n; ++k) x.push_back(a * std::pow(b / a, k / double(n - 1)));
  return x;
}

}  // namespace

TEST(SteadyShear, CardanoRootSolvesTheCubic) {
  for (double c : {0.0, 1e-8, 0.01, 1.0, 1e6}) {
    const double f = peterlin_cardano(c);
    EXPECT_NEAR(f * f * (f - 1), c, 1e-14 * std::max(1.0, c) * f * f) << c;
  }
}

TEST(SteadyShear, OwensIsTheCrossLaw) {
  const OwensParameters o;
  const double eta0 = o.eta_s + o.eta_p0;
  for (bool log_form : {false, true}) {
    const Law law{FluidModel::Owens, log_form, false, 4.95e-4, 1.0, o.beta(), 0.0, o};
    const std::vector<double> rates = logspace(1e-3, 1e4, 29);  // 1/s
    std::vector<double> gdots;
    for (double r : rates) gdots.push_back(r * law.Gamma / o.rate_scale);  // model units
    const std::vector<double> eta = viscosities(law, gdots);
    double worst = 0;
    for (size_t k = 0; k < rates.size(); ++k) {
      const double r = rates[k];
      auto cross = [&](double rate) {
        const double x = std::pow(rate, o.m);
        return o.eta_s + o.eta_p0 * (1 + o.theta2 * o.eta_pinf / o.eta_p0 * x) / (1 + o.theta2 * x);  // Pa s
      };
      const double regularised = cross(std::hypot(r, o.rate_floor));
      EXPECT_NEAR(eta[k] * eta0, regularised, 1e-10 * regularised) << (log_form ? "log" : "conf") << " r = " << r;
      worst = std::max(worst, std::abs(eta[k] * eta0 / regularised - 1));
      // The floor changes ln r by ln(1 + (floor/r)^2)/2 <= (floor/r)^2 / 2, and
      // |d ln eta / d ln r| <= m, so the relative change is at most m (floor/r)^2 / 2.
      const double bound = o.m * 0.5 * std::pow(o.rate_floor / r, 2);
      EXPECT_NEAR(eta[k] * eta0, cross(r), (bound + 1e-10) * cross(r)) << "r = " << r;
    }
    std::printf("Owens %s: largest relative deviation from the Cross law %.1e\n", log_form ? "log" : "conf", worst);
    // the range spans the law: from near eta_s + eta_p0 down to near eta_s + eta_pinf
    EXPECT_GT(eta.front() * eta0, 0.95 * eta0);
    EXPECT_LT(eta.back() * eta0, 1.1 * (o.eta_s + o.eta_pinf));
  }
}

TEST(SteadyShear, FenePIsTheClosedForm) {
  for (bool log_form : {false, true})
    for (bool dynamic : {false, true})
      for (double b : {2.0, 5.0, 20.0, 100.0}) {
        const Law law{FluidModel::FeneP, log_form, dynamic, 1.0, 0.5, 0.2, b, {}};
        const std::vector<double> W = logspace(1e-3, 1e3, 25);  // lambda gdot
        std::vector<double> gdots;
        for (double w : W) gdots.push_back(w * law.Gamma / law.Wi);
        const std::vector<double> eta = viscosities(law, gdots);
        double worst = 0;
        for (size_t k = 0; k < W.size(); ++k) {
          const double f = peterlin_cardano(2 * W[k] * W[k] / (3 * b));
          const double closed = law.beta + (1 - law.beta) / f;
          EXPECT_NEAR(eta[k], closed, 1e-10 * closed)
              << (log_form ? "log" : "conf") << (dynamic ? " zz" : "") << " b = " << b << " W = " << W[k];
          worst = std::max(worst, std::abs(eta[k] / closed - 1));
        }
        std::printf("FENE-P %s%s b = %g: largest relative deviation from the closed form %.1e\n",
                    log_form ? "log" : "conf", dynamic ? " zz" : "", b, worst);
      }
}

TEST(SteadyShear, OldroydBHasConstantViscosity) {
  for (bool log_form : {false, true}) {
    const Law law{FluidModel::OldroydB, log_form, false, 1.0, 0.5, 0.3, 0.0, {}};
    const std::vector<double> gdots = logspace(1e-3, 1e2, 11);
    for (double eta : viscosities(law, gdots)) EXPECT_NEAR(eta, 1.0, 1e-12);
  }
}
