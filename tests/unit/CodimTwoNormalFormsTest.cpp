// Normal forms at the codimension-two points of Hopf curves (stability/TimeFormNormalForms.cpp):
// Bogdanov-Takens and fold-Hopf points of constructed normal forms, whose coefficients are known
// in closed form, and of a quadratic system with a non-symmetric mass matrix against a dense
// evaluation of Kuznetsov's formulas. (Folds, cusps, branch points and Hopf points:
// NormalFormsTest.cpp.)
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "stability/NormalForms.hpp"

using namespace keller;

namespace {

// A problem of three unknowns with a full Jacobian pattern and the parameters beta1, beta2 (zero),
// B = I unless a subclass says otherwise.
class ThreeUnknowns : public Problem {
 public:
  ThreeUnknowns() {
    params_.add("beta1", 0.0, "unfolding");
    params_.add("beta2", 0.0, "unfolding");
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) t.emplace_back(i, j, 0.0);
    pattern_.resize(3, 3);
    pattern_.setFromTriplets(t.begin(), t.end());
    pattern_.makeCompressed();
  }
  int size() const override { return 3; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Vector initial_guess() override { return Vector::Zero(3); }
  Status mass_matrix(const Vector&, SparseMatrix& B) override {
    B = pattern_;
    for (int i = 0; i < 3; ++i) B.coeffRef(i, i) = weights()[i];
    return {};
  }
  Status time_residual(const Vector&, const Vector& udot, Vector& R) override {
    R = udot.cwiseProduct(weights());
    return {};
  }

 protected:
  virtual Vector weights() const { return Vector::Ones(3); }  // B's diagonal
  ParameterSet params_;
  SparseMatrix pattern_;
};

// Kuznetsov's Bogdanov-Takens normal form x1' = x2, x2' = beta1 + beta2 x2 + a0 x1^2 + b0 x1 x2 + k x3
// with a third variable tau x3' = -x3 + x1^2 (B = diag(1, 1, tau)): on the centre manifold x3 =
// x1^2 - 2 tau x1 x2 + ..., so the planar normal form has a = a0 + k and b = b0 - 2 k tau, with
// q0 = (1, 0, 0) (unit, positive). Both the coupling through the third variable and the mass matrix
// enter b; a formula without B would give b0 - 2 k.
class ReducedBogdanovTakens final : public ThreeUnknowns {
 public:
  static constexpr double a0 = 1.3, b0 = -0.6, k = 0.7, tau = 0.5;
  std::string name() const override { return "reduced-bogdanov-takens"; }
  Status residual(const Vector& x, Vector& F) override {  // B x' = -F
    const double beta1 = params_.value(0), beta2 = params_.value(1);
    F.resize(3);
    F[0] = -x[1];
    F[1] = -(beta1 + beta2 * x[1] + a0 * x[0] * x[0] + b0 * x[0] * x[1] + k * x[2]);
    F[2] = x[2] - x[0] * x[0];
    return {};
  }
  Status jacobian(const Vector& x, Vector& F, SparseMatrix& J) override {
    residual(x, F);
    const double beta2 = params_.value(1);
    J = pattern_;
    J.coeffRef(0, 1) = -1.0;
    J.coeffRef(1, 0) = -(2 * a0 * x[0] + b0 * x[1]);
    J.coeffRef(1, 1) = -(beta2 + b0 * x[0]);
    J.coeffRef(1, 2) = -k;
    J.coeffRef(2, 0) = -2 * x[0];
    J.coeffRef(2, 2) = 1.0;
    return {};
  }

 protected:
  Vector weights() const override { return Eigen::Vector3d(1.0, 1.0, tau); }
};

TEST(NormalForms, BogdanovTakensCoefficientsAreThoseOfTheReducedEquation) {
  ReducedBogdanovTakens problem;
  NormalForm nf;
  ASSERT_TRUE(NormalForms().bogdanov_takens(problem, 0, Vector::Zero(3), nf).is_ok());
  using P = ReducedBogdanovTakens;
  // second differences of a quadratic: exact up to rounding at the 1e-3 steps
  EXPECT_EQ(nf.type, "Bogdanov-Takens");
  EXPECT_NEAR(nf.a, P::a0 + P::k, 1e-8) << nf.summary();
  EXPECT_NEAR(nf.b, P::b0 - 2 * P::k * P::tau, 1e-8) << nf.summary();
  EXPECT_NEAR(nf.phi[0], 1.0, 1e-12);
}

// Kuznetsov's fold-Hopf normal form itself: x' = beta1 + b x^2 + c (y^2 + z^2), and for zeta = y + i z,
// zeta' = (beta2 + i omega) zeta + d x zeta (F = -rhs, B = I). With q0 = (1, 0, 0) and q1 = (0, 1,
// -i) / sqrt 2 (unit, first entry real and positive), zeta = sqrt 2 w1, so g200 = 2 b, g011 = 2 c
// and g110 = d.
class ReducedFoldHopf final : public ThreeUnknowns {
 public:
  static constexpr double b = 0.8, c = -0.5, dr = 0.3, di = 0.7, omega = 2.0;
  std::string name() const override { return "reduced-fold-hopf"; }
  Status residual(const Vector& u, Vector& F) override {
    const double x = u[0], y = u[1], z = u[2], beta1 = params_.value(0), beta2 = params_.value(1);
    F.resize(3);
    F[0] = -(beta1 + b * x * x + c * (y * y + z * z));
    F[1] = -(beta2 * y - omega * z + x * (dr * y - di * z));
    F[2] = -(omega * y + beta2 * z + x * (di * y + dr * z));
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    const double x = u[0], y = u[1], z = u[2], beta2 = params_.value(1);
    J = pattern_;
    J.coeffRef(0, 0) = -2 * b * x;
    J.coeffRef(0, 1) = -2 * c * y;
    J.coeffRef(0, 2) = -2 * c * z;
    J.coeffRef(1, 0) = -(dr * y - di * z);
    J.coeffRef(1, 1) = -(beta2 + dr * x);
    J.coeffRef(1, 2) = -(-omega - di * x);
    J.coeffRef(2, 0) = -(di * y + dr * z);
    J.coeffRef(2, 1) = -(omega + di * x);
    J.coeffRef(2, 2) = -(beta2 + dr * x);
    return {};
  }
};

TEST(NormalForms, FoldHopfCoefficientsAreThoseOfTheNormalForm) {
  ReducedFoldHopf problem;
  NormalForm nf;
  ASSERT_TRUE(NormalForms().fold_hopf(problem, 0, Vector::Zero(3), 1.9, nf).is_ok());
  using P = ReducedFoldHopf;
  // second differences of a quadratic: exact up to rounding at the 1e-3 steps
  EXPECT_EQ(nf.type, "fold-Hopf");
  EXPECT_NEAR(nf.omega, P::omega, 1e-10);
  EXPECT_NEAR(nf.a, 2 * P::b, 1e-8) << nf.summary();
  EXPECT_NEAR(nf.b, 2 * P::c, 1e-8) << nf.summary();
  EXPECT_NEAR(nf.c1.real(), P::dr, 1e-8) << nf.summary();
  EXPECT_NEAR(nf.c1.imag(), P::di, 1e-8) << nf.summary();
  EXPECT_NEAR(nf.c, P::dr / (2 * P::b), 1e-8);  // theta
  EXPECT_NE(nf.summary().find("s = -1"), std::string::npos) << nf.summary();
  // its zero is simple: no Bogdanov-Takens point, and bogdanov_takens says so instead of numbers
  const Status bt = NormalForms().bogdanov_takens(problem, 0, Vector::Zero(3), nf);
  EXPECT_EQ(bt.code(), StatusCode::InvalidState);
  EXPECT_NE(bt.message().find("not a Bogdanov-Takens point"), std::string::npos) << bt.message();
}

// B u' = L u + Q(u, u) (F = -(L u + Q(u, u)) - beta1 e1) with a constant, non-symmetric B and A =
// B^-1 L = S Lambda S^-1 in a non-orthogonal basis S: Lambda the Jordan block [0 1; 0 0] and -1
// (Bogdanov-Takens), or 0 and the rotation [0 -omega; omega 0] (fold-Hopf). Kuznetsov's vectors are
// then S's columns and S^-1's rows (scaled to keller's normalisation), and f_uu[x, y] = 2 B^-1 Q(x,
// y): a reference in A's coordinates, independent of the adjoint, transposed, bordered and shifted
// solves with J = -L and B that NormalForms makes. A left vector taken with B for B^T, or a wrong
// conjugate, changes the numbers (B and S have no symmetry).
class QuadraticSystem final : public ThreeUnknowns {
 public:
  QuadraticSystem(const Eigen::Matrix3d& lambda) {
    S_ << 1.0, 0.4, -0.3, 0.2, 1.0, 0.5, -0.1, 0.3, 1.0;
    B_ << 1.0, 0.3, 0.0, -0.2, 0.8, 0.1, 0.0, 0.25, 1.2;
    L_ = B_ * S_ * lambda * S_.inverse();
    Q_[0] << 0.7, -0.2, 0.3, -0.2, 0.5, 0.1, 0.3, 0.1, -0.4;
    Q_[1] << -0.3, 0.6, 0.2, 0.6, 0.1, -0.5, 0.2, -0.5, 0.8;
    Q_[2] << 0.4, 0.1, -0.6, 0.1, -0.7, 0.2, -0.6, 0.2, 0.3;
  }
  std::string name() const override { return "quadratic-system"; }
  Status residual(const Vector& u, Vector& F) override {
    F = -(L_ * u + quadratic(u, u).real());
    F[0] -= params_.value(0);
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    Eigen::Matrix3d M = -L_;
    for (int i = 0; i < 3; ++i) M.row(i) -= 2.0 * (Q_[i] * u).transpose();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) J.coeffRef(i, j) = M(i, j);
    return {};
  }
  Status mass_matrix(const Vector&, SparseMatrix& B) override {
    B = pattern_;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) B.coeffRef(i, j) = B_(i, j);
    return {};
  }
  Status time_residual(const Vector&, const Vector& udot, Vector& R) override {
    R.resize(3);  // by loops: GCC's avx512 loads of a 3 x 3 product draw a false array-bounds warning
    for (int i = 0; i < 3; ++i) R[i] = B_.row(i).dot(Eigen::Vector3d(udot));
    return {};
  }
  // Q(x, y)_i = x^T Q_i y, bilinear (no conjugate)
  Eigen::Vector3cd quadratic(const Eigen::Vector3cd& x, const Eigen::Vector3cd& y) const {
    Eigen::Vector3cd r;
    for (int i = 0; i < 3; ++i) r[i] = x.transpose() * Q_[i].cast<std::complex<double>>() * y;
    return r;
  }
  Eigen::Vector3cd f_uu(const Eigen::Vector3cd& x, const Eigen::Vector3cd& y) const {
    return 2.0 * B_.inverse().cast<std::complex<double>>() * quadratic(x, y);
  }
  Eigen::Matrix3d S_, B_, L_;
  std::array<Eigen::Matrix3d, 3> Q_;
};

TEST(NormalForms, BogdanovTakensAndFoldHopfAgainstADenseReferenceWithANonSymmetricMassMatrix) {
  using C = std::complex<double>;
  using V = Eigen::Vector3cd;
  {
    Eigen::Matrix3d jordan;
    jordan << 0, 1, 0, 0, 0, 0, 0, 0, -1;
    QuadraticSystem problem(jordan);
    NormalForm nf;
    ASSERT_TRUE(NormalForms().bogdanov_takens(problem, 0, Vector::Zero(3), nf).is_ok());
    // q0 = S e1 / s, q1 = S e2 / s, p0 = s (S^-1)_1, p1 = s (S^-1)_2 with s = |S e1| (its largest entry > 0)
    const Eigen::Matrix3d W = problem.S_.inverse();
    const double scale = problem.S_.col(0).norm();
    const V q0 = (problem.S_.col(0) / scale).cast<C>(), q1 = (problem.S_.col(1) / scale).cast<C>();
    const V p0 = (W.row(0).transpose() * scale).cast<C>(), p1 = (W.row(1).transpose() * scale).cast<C>();
    const C a = 0.5 * p1.dot(problem.f_uu(q0, q0)), b = p0.dot(problem.f_uu(q0, q0)) + p1.dot(problem.f_uu(q0, q1));
    EXPECT_NEAR(nf.a, a.real(), 1e-8 * std::abs(a)) << nf.summary();
    EXPECT_NEAR(nf.b, b.real(), 1e-8 * std::abs(b)) << nf.summary();
  }
  {
    const double omega = 1.7;
    Eigen::Matrix3d rotation;
    rotation << 0, 0, 0, 0, 0, -omega, 0, omega, 0;
    QuadraticSystem problem(rotation);
    NormalForm nf;
    ASSERT_TRUE(NormalForms().fold_hopf(problem, 0, Vector::Zero(3), 1.6, nf).is_ok());
    const Eigen::Matrix3d W = problem.S_.inverse();
    const Eigen::Matrix3cd Sc = problem.S_.cast<C>(), Wc = W.cast<C>();
    // A q1 = i omega q1: q1 = S (e2 - i e3); p1^H A = i omega p1^H: p1^H = (S^-1)_2 + i (S^-1)_3
    V q0 = Sc.col(0), q1 = Sc.col(1) - C(0, 1) * Sc.col(2);
    Eigen::Index k = 0;
    q0.cwiseAbs().maxCoeff(&k);
    q0 /= q0.norm() * (q0[k].real() > 0 ? 1.0 : -1.0);
    q1.cwiseAbs().maxCoeff(&k);
    q1 *= std::conj(q1[k]) / std::abs(q1[k]) / q1.norm();
    V p0 = Wc.row(0).transpose(), p1 = (Wc.row(1) + C(0, 1) * Wc.row(2)).adjoint();
    p0 /= p0.dot(q0);             // p0 real: <p0, q0> = 1
    p1 /= std::conj(p1.dot(q1));  // <p1, q1> = p1^H q1 = 1
    const C g200 = p0.dot(problem.f_uu(q0, q0)), g011 = p0.dot(problem.f_uu(q1, q1.conjugate())),
            g110 = p1.dot(problem.f_uu(q0, q1));
    EXPECT_NEAR(nf.omega, omega, 1e-10);
    EXPECT_NEAR(nf.a, g200.real(), 1e-8 * std::abs(g200)) << nf.summary();
    EXPECT_NEAR(nf.b, g011.real(), 1e-8 * std::abs(g011)) << nf.summary();
    EXPECT_NEAR(std::abs(nf.c1 - g110), 0.0, 1e-8 * std::abs(g110)) << nf.summary();
  }
}

}  // namespace
