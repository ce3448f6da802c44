// The reference operator of the manufactured solutions checked on its own, before it judges the
// kernels: the manufactured velocity is solenoidal, the series exp agrees with the eigenbasis
// exp, the strong form vanishes on the closed-form steady states of simple shear and planar
// elongation (which fixes the upper-convected derivative's K M + M K^T against a transposed
// gradient), and its log-conformation operator Dexp_Psi^{-1}[K M + M K^T] equals the
// Fattal-Kupferman decomposition (Omega Psi - Psi Omega) + 2 B computed in the eigenbasis.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "mms/ManufacturedFields.hpp"
#include "mms/StrongForm.hpp"

using namespace keller;
using namespace keller::mms;

namespace {

// Homogeneous flow v = G x with a constant conformation M and pressure.
struct Homogeneous {
  double G[2][2];
  double M[4];
  template <class S>
  void velocity(const S (&x)[2], S (&v)[2]) const {
    v[0] = G[0][0] * x[0] + G[0][1] * x[1];
    v[1] = G[1][0] * x[0] + G[1][1] * x[1];
  }
  template <class S>
  S pressure(const S (&)[2]) const {
    return S(0.3);
  }
  template <class S>
  void conformation(const S (&)[2], S (&m)[4]) const {
    for (int c = 0; c < 4; ++c) m[c] = S(M[c]);
  }
};

double max_abs(const double (&s)[4], int n) {
  double m = 0;
  for (int c = 0; c < n; ++c) m = std::max(m, std::abs(s[c]));
  return m;
}

}  // namespace

TEST(StrongForm, ManufacturedVelocityIsSolenoidal) {
  const StrongForm<ManufacturedFields> sf({}, {});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-0.2, 1.2);
  for (int k = 0; k < 100; ++k) {
    const double x[2] = {U(rng), U(rng)};
    double v[2], K[2][2];
    sf.velocity_gradient(x, v, K);
    EXPECT_LT(std::abs(K[0][0] + K[1][1]), 1e-15);
  }
}

TEST(StrongForm, SeriesExpMatchesEigenbasisExp) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> U(-2, 2);
  for (int k = 0; k < 100; ++k) {
    const double p[3] = {U(rng), U(rng), U(rng)};
    double e[3];
    series_exp(p, e);
    Eigen::Matrix2d P;
    P << p[0], p[1], p[1], p[2];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(P);
    const Eigen::Matrix2d E =
        es.eigenvectors() * es.eigenvalues().array().exp().matrix().asDiagonal() * es.eigenvectors().transpose();
    const double scale = E.cwiseAbs().maxCoeff();
    EXPECT_NEAR(e[0], E(0, 0), 1e-14 * scale);
    EXPECT_NEAR(e[1], E(0, 1), 1e-14 * scale);
    EXPECT_NEAR(e[2], E(1, 1), 1e-14 * scale);
  }
}

// model.md: simple shear v = (gdot y, 0) at W = lambda gdot: M_xx = 1 + 2 W^2, M_xy = W, M_yy = 1
// (Oldroyd-B); FENE-P: f^2 (f - 1) = 2 W^2 / (3 b), M_yy = M_zz = 1/f, M_xy = W/f^2,
// M_xx = (1 + 2 W^2/f^2)/f. Planar elongation v = (eps x, -eps y): M_xx = 1/(1 - 2W),
// M_yy = 1/(1 + 2W) (Oldroyd-B). Homogeneous states have no momentum source either.
TEST(StrongForm, VanishesOnSteadyHomogeneousStates) {
  FluidSpec fl;
  fl.model = FluidModel::OldroydB;
  fl.Gamma = 1.0;
  fl.Wi = 0.7;
  fl.beta = 0.3;
  const double x[2] = {0.3, 0.8};
  for (double gdot : {0.5, 2.0}) {
    const double W = fl.Wi / fl.Gamma * gdot;
    const StrongForm<Homogeneous> sf(fl, Homogeneous{{{0, gdot}, {0, 0}}, {1 + 2 * W * W, W, 1, 1}});
    double s[4], f[2];
    sf.constitutive_source(x, s);
    sf.momentum_source(x, f);
    EXPECT_LT(max_abs(s, 3), 1e-14 * (1 + 2 * W * W));
    EXPECT_LT(std::hypot(f[0], f[1]), 1e-14);
    // the transposed state (M_yy = 1 + 2 W^2, M_xx = 1) is not a solution
    const StrongForm<Homogeneous> wrong(fl, Homogeneous{{{0, gdot}, {0, 0}}, {1, W, 1 + 2 * W * W, 1}});
    wrong.constitutive_source(x, s);
    EXPECT_GT(max_abs(s, 3), 0.1);
  }
  for (double eps : {0.2, 0.6}) {
    const double W = fl.Wi / fl.Gamma * eps;
    const StrongForm<Homogeneous> sf(fl, Homogeneous{{{eps, 0}, {0, -eps}}, {1 / (1 - 2 * W), 0, 1 / (1 + 2 * W), 1}});
    double s[4];
    sf.constitutive_source(x, s);
    EXPECT_LT(max_abs(s, 3), 1e-14 / (1 - 2 * W));
  }
  for (bool dynamic : {false, true}) {
    FluidSpec fp = fl;
    fp.model = FluidModel::FeneP;
    fp.dynamic_zz = dynamic;
    for (double b : {2.0, 50.0}) {
      fp.b = b;
      const double gdot = 3.0, W = fp.Wi / fp.Gamma * gdot, c = 2 * W * W / (3 * b);
      double f = 1 + c;  // Newton on f^2 (f - 1) = c from above
      for (int it = 0; it < 100; ++it) f -= (f * f * (f - 1) - c) / (3 * f * f - 2 * f);
      const StrongForm<Homogeneous> sf(
          fp, Homogeneous{{{0, gdot}, {0, 0}}, {(1 + 2 * W * W / (f * f)) / f, W / (f * f), 1 / f, 1 / f}});
      double s[4];
      sf.constitutive_source(x, s);
      EXPECT_LT(max_abs(s, dynamic ? 4 : 3), 1e-13) << "b = " << b << (dynamic ? " dynamic zz" : "");
    }
  }
}

// Dexp_Psi^{-1}[K M + M K^T] against Fattal and Kupferman's B = R diag(Kt11, Kt22) R^T,
// Omega = R [[0, w], [-w, 0]] R^T, w = (m2 Kt12 + m1 Kt21) / (m2 - m1), Kt = R^T K R.
TEST(StrongForm, LogOperatorIsTheFattalKupfermanDecomposition) {
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int k = 0; k < 50; ++k) {
    const double psi[3] = {U(rng), U(rng), U(rng)};
    Eigen::Matrix2d K;
    K << U(rng), U(rng), U(rng), U(rng);
    // conformation-form residual at rest-free relaxation: only the stretch, M from psi
    double m[3];
    series_exp(psi, m);
    Eigen::Matrix2d M, P;
    M << m[0], m[1], m[1], m[2];
    P << psi[0], psi[1], psi[1], psi[2];
    const Eigen::Matrix2d stretch = K * M + M * K.transpose();
    using D3 = Eigen::AutoDiffScalar<Eigen::Vector3d>;
    const D3 p[3] = {D3(psi[0], 3, 0), D3(psi[1], 3, 1), D3(psi[2], 3, 2)};
    D3 e[3];
    series_exp(p, e);
    Eigen::Matrix3d J;
    for (int r = 0; r < 3; ++r) J.row(r) = e[r].derivatives().transpose();
    const Eigen::Vector3d t = J.partialPivLu().solve(Eigen::Vector3d(stretch(0, 0), stretch(0, 1), stretch(1, 1)));

    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(P);
    const Eigen::Matrix2d R = es.eigenvectors();
    const double m1 = std::exp(es.eigenvalues()[0]), m2 = std::exp(es.eigenvalues()[1]);
    const Eigen::Matrix2d Kt = R.transpose() * K * R;
    const double w = (m2 * Kt(0, 1) + m1 * Kt(1, 0)) / (m2 - m1);
    Eigen::Matrix2d Bt = Eigen::Matrix2d::Zero(), Wt;
    Bt(0, 0) = Kt(0, 0);
    Bt(1, 1) = Kt(1, 1);
    Wt << 0, w, -w, 0;
    const Eigen::Matrix2d Om = R * Wt * R.transpose(), B = R * Bt * R.transpose();
    const Eigen::Matrix2d fk = Om * P - P * Om + 2 * B;
    const double tol = 1e-12 * (1 + std::abs(w));
    EXPECT_NEAR(t[0], fk(0, 0), tol);
    EXPECT_NEAR(t[1], fk(0, 1), tol);
    EXPECT_NEAR(t[2], fk(1, 1), tol);
  }
}
