// Log-conformation algebra: exp and log of symmetric 2x2 matrices, the invariant form of
// (Omega Psi - Psi Omega) + 2B against its eigenbasis definition, the log equation as an exact
// rewriting of the conformation equation (independent of that definition), and exact, finite
// derivatives where the eigenvalues coincide.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "core/AutoDiff.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/LogConformation.hpp"

using namespace keller;

namespace {

Eigen::Matrix2d mat(const Sym2<double>& s) {
  Eigen::Matrix2d m;
  m << s.xx, s.xy, s.xy, s.yy;
  return m;
}

// Fattal-Kupferman in the eigenbasis of M = exp(Psi): B = R diag(Lt11, Lt22) R^T,
// Omega = R [[0, w], [-w, 0]] R^T, w = (m2 Lt12 + m1 Lt21) / (m2 - m1).
Eigen::Matrix2d fk_reference(const Sym2<double>& psi, const Eigen::Matrix2d& L) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(mat(psi));
  const Eigen::Matrix2d R = es.eigenvectors();
  const double p1 = es.eigenvalues()[0], p2 = es.eigenvalues()[1];
  const double m1 = std::exp(p1), m2 = std::exp(p2);
  const Eigen::Matrix2d Lt = R.transpose() * L * R;
  const double w = (m2 * Lt(0, 1) + m1 * Lt(1, 0)) / (m2 - m1);
  Eigen::Matrix2d Bt = Eigen::Matrix2d::Zero(), Wt;
  Bt(0, 0) = Lt(0, 0);
  Bt(1, 1) = Lt(1, 1);
  Wt << 0, w, -w, 0;
  const Eigen::Matrix2d Om = R * Wt * R.transpose(), B = R * Bt * R.transpose(), Psi = mat(psi);
  return Om * Psi - Psi * Om + 2 * B;
}

}  // namespace

TEST(LogConformation, ExpAndLogInvertEachOther) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-2, 2);
  for (int k = 0; k < 50; ++k) {
    const Sym2<double> psi{U(rng), U(rng), U(rng)};
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(mat(psi));
    const Eigen::Matrix2d ref =
        es.eigenvectors() * es.eigenvalues().array().exp().matrix().asDiagonal() * es.eigenvectors().transpose();
    const Sym2<double> M = sym_exp(psi);
    EXPECT_LT((mat(M) - ref).cwiseAbs().maxCoeff(), 1e-13 * ref.cwiseAbs().maxCoeff());
    const Sym2<double> back = sym_log(M);
    EXPECT_LT((mat(back) - mat(psi)).cwiseAbs().maxCoeff(), 1e-12);
  }
  // near-equal eigenvalues take the series branches
  const Sym2<double> tiny{1e-9, 2e-9, -3e-9};
  EXPECT_LT((mat(sym_log(sym_exp(tiny))) - mat(tiny)).cwiseAbs().maxCoeff(), 1e-15);  // rounding of exp's 1
}

TEST(LogConformation, InvariantFormMatchesTheEigenbasisForm) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(-1.5, 1.5);
  double worst = 0;
  for (int k = 0; k < 200; ++k) {
    const Sym2<double> psi{U(rng), U(rng), U(rng)};
    double L[2][2] = {{U(rng), U(rng)}, {U(rng), U(rng)}};
    const Eigen::Matrix2d Lm = (Eigen::Matrix2d() << L[0][0], L[0][1], L[1][0], L[1][1]).finished();
    const Sym2<double> t = log_conformation_stretch(psi, L);
    const Eigen::Matrix2d ref = fk_reference(psi, Lm);
    worst = std::max(worst, (mat(t) - ref).cwiseAbs().maxCoeff() / std::max(1.0, ref.cwiseAbs().maxCoeff()));
  }
  EXPECT_LT(worst, 1e-12);
  // at Psi = 0 the term is L + L^T (so that M = I + Psi gives back the conformation equation)
  const double L[2][2] = {{0.3, -1.2}, {0.7, 0.4}};
  const Sym2<double> t0 = log_conformation_stretch(Sym2<double>{0, 0, 0}, L);
  EXPECT_DOUBLE_EQ(t0.xx, 0.6);
  EXPECT_DOUBLE_EQ(t0.xy, -0.5);
  EXPECT_DOUBLE_EQ(t0.yy, 0.8);
}

// The two forms are one equation: along any path Psi(t), d/dt exp(Psi) = D exp(Psi)[dPsi/dt], so
// the log residual R_log = v . grad Psi - T(L, Psi) + P(M) M^-1 / lambda and the conformation
// residual R = v . grad M - L M - M L^T + P(M) / lambda of M = exp(Psi) must satisfy
// R = D exp(Psi)[R_log] pointwise, for any L (not only traceless ones), any law's P(M) and any
// convective derivative. D exp(Psi)[X] is taken exactly, by a dual number along X; every law
// with a relaxation of its own (FENE-P's f = (b - 2/3) / (b - tr M / 3), Giesekus' quadratic
// term, PTT's Y, FENE-CR's f on both terms) and a relaxation rate 1/lambda = 2.5 are used. A
// transposed L, a sign, or a wrong factor in T or in the relaxation term breaks this at O(1), far
// above rounding.
TEST(LogConformation, LogResidualMapsToTheConformationResidual) {
  const struct {
    FluidModel model;
    LawConstants<double> c;
  } laws[] = {{FluidModel::OldroydB, {}},
              {FluidModel::FeneP, {50.0}},
              {FluidModel::Giesekus, {50.0, 0.3}},
              {FluidModel::PttLinear, {50.0, 0.0, 0.25}},
              {FluidModel::PttExponential, {50.0, 0.0, 0.25}},
              {FluidModel::FeneCr, {50.0}}};
  for (const auto& law : laws) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1.5, 1.5);
    const double inv_lambda = 2.5;
    double worst = 0;
    for (int n = 0; n < 200; ++n) {
      const Sym2<double> psi{U(rng), U(rng), U(rng)};
      const double L[2][2] = {{U(rng), U(rng)}, {U(rng), U(rng)}};
      const Sym2<double> conv{U(rng), U(rng), U(rng)};  // v . grad Psi at the point
      const Sym2<double> M = sym_exp(psi);
      const Relaxation<double> k = relaxation(law.model, false, Conformation<double>{M.xx, M.xy, M.yy, 1.0}, law.c);
      const Sym2<double> rate = log_conformation_rate(psi, L, k, M, inv_lambda);
      const Sym2<double> R_log{conv.xx + rate.xx, conv.xy + rate.xy, conv.yy + rate.yy};
      // D exp(Psi)[X]: exp(Psi + eps X) with eps a dual variable
      auto dexp = [&](const Sym2<double>& X) {
        const Dual<1> eps = make_variable<1>(0.0, 0);
        const Sym2<Dual<1>> E = sym_exp(Sym2<Dual<1>>{psi.xx + eps * X.xx, psi.xy + eps * X.xy, psi.yy + eps * X.yy});
        return Sym2<double>{E.xx.derivatives()[0], E.xy.derivatives()[0], E.yy.derivatives()[0]};
      };
      const Sym2<double> lhs = dexp(R_log), v_grad_M = dexp(conv);
      const Conformation<double> c = conformation_rate(Conformation<double>{M.xx, M.xy, M.yy, 1.0}, L, k, inv_lambda);
      const double rhs[3] = {v_grad_M.xx + c.xx, v_grad_M.xy + c.xy, v_grad_M.yy + c.yy};
      const double l[3] = {lhs.xx, lhs.xy, lhs.yy};
      const double scale = std::max({1.0, std::abs(rhs[0]), std::abs(rhs[1]), std::abs(rhs[2]), M.xx, M.yy});
      for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(l[i] - rhs[i]) / scale);
    }
    EXPECT_LT(worst, 1e-12) << to_string(law.model);
  }
}

// Dual-number derivatives at and near M = I against central differences: finite and exact,
// and continuous across the switch between the series and the closed form.
TEST(LogConformation, DerivativesAreExactWhereEigenvaluesCoincide) {
  const double L[2][2] = {{0.3, -1.2}, {0.7, 0.4}};
  for (double scale : {0.0, 1e-9, 1e-5, 0.0316, 0.0317, 0.3}) {  // rho^2 = 1e-3 lies at 0.0316..0.0317
    const double p0[3] = {0.2 + scale, scale * 0.5, 0.2 - scale};
    for (int dir = 0; dir < 3; ++dir) {
      Dual<3> p[3] = {Dual<3>(p0[0]), Dual<3>(p0[1]), Dual<3>(p0[2])};
      p[dir] = make_variable<3>(p0[dir], dir);
      const Sym2<Dual<3>> t = log_conformation_stretch(Sym2<Dual<3>>{p[0], p[1], p[2]}, L);
      const Sym2<Dual<3>> e = sym_exp(Sym2<Dual<3>>{p[0], p[1], p[2]});
      const double h = 1e-6;
      double pp[3] = {p0[0], p0[1], p0[2]}, pm[3] = {p0[0], p0[1], p0[2]};
      pp[dir] += h;
      pm[dir] -= h;
      const Sym2<double> tp = log_conformation_stretch(Sym2<double>{pp[0], pp[1], pp[2]}, L);
      const Sym2<double> tm = log_conformation_stretch(Sym2<double>{pm[0], pm[1], pm[2]}, L);
      const Sym2<double> ep = sym_exp(Sym2<double>{pp[0], pp[1], pp[2]}),
                         em = sym_exp(Sym2<double>{pm[0], pm[1], pm[2]});
      const double fd[6] = {(tp.xx - tm.xx) / (2 * h), (tp.xy - tm.xy) / (2 * h), (tp.yy - tm.yy) / (2 * h),
                            (ep.xx - em.xx) / (2 * h), (ep.xy - em.xy) / (2 * h), (ep.yy - em.yy) / (2 * h)};
      const double ad[6] = {t.xx.derivatives()[dir], t.xy.derivatives()[dir], t.yy.derivatives()[dir],
                            e.xx.derivatives()[dir], e.xy.derivatives()[dir], e.yy.derivatives()[dir]};
      for (int k = 0; k < 6; ++k) {
        EXPECT_TRUE(std::isfinite(ad[k]));
        EXPECT_NEAR(ad[k], fd[k], 1e-8) << "scale " << scale << " direction " << dir << " entry " << k;
      }
    }
  }
}
