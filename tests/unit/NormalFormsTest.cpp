// Normal forms of located points against closed forms (stability/NormalForms.hpp): a fold's
// curvature from a problem with a known reduced equation, the discrete pitchfork's cubic
// coefficient, the Brusselator's first Lyapunov coefficient, frequency, transversality and orbit
// amplitude; and the derivatives they are built on: hyper-dual numbers against closed-form
// derivatives, and the exact (hyper-dual) derivatives of the collapsible channel's kernels against
// central differences of its residual.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include "core/HigherDerivatives.hpp"
#include "core/HyperDual.hpp"
#include "core/Newton.hpp"
#include "problems/analytic/Brusselator1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "problems/channel/CollapsibleChannelProblem.hpp"
#include "stability/NormalForms.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

// f''' at x by a hyper-dual number seeded along 1 in all three units
template <class F>
double third_derivative(F f, double x) {
  return mixed_part<3>(f(seeded<3>(x, {1.0, 1.0, 1.0})));
}

TEST(HyperDual, ThirdDerivativesOfEveryFunctionAgainstClosedForms) {
  const double x = 0.7, t = std::tanh(x);
  using H = HyperDual<3>;
  EXPECT_NEAR(third_derivative([](H v) { return exp(v); }, x), std::exp(x), 1e-14);
  EXPECT_NEAR(third_derivative([](H v) { return log(v); }, x), 2.0 / (x * x * x), 1e-13);
  EXPECT_NEAR(third_derivative([](H v) { return pow(v, 2.5); }, x), 2.5 * 1.5 * 0.5 * std::pow(x, -0.5), 1e-13);
  EXPECT_NEAR(third_derivative([](H v) { return sqrt(v); }, x), 0.375 * std::pow(x, -2.5), 1e-13);
  EXPECT_NEAR(third_derivative([](H v) { return cosh(v); }, x), std::sinh(x), 1e-14);
  EXPECT_NEAR(third_derivative([](H v) { return sinh(v); }, x), std::cosh(x), 1e-14);
  EXPECT_NEAR(third_derivative([](H v) { return tanh(v); }, x), (1 - t * t) * (6 * t * t - 2), 1e-14);
  EXPECT_NEAR(third_derivative([](H v) { return sin(v); }, x), -std::cos(x), 1e-14);
  EXPECT_NEAR(third_derivative([](H v) { return cos(v); }, x), std::sin(x), 1e-14);
  EXPECT_NEAR(third_derivative([](H v) { return 1.0 / v; }, x), -6.0 / std::pow(x, 4), 1e-12);
  EXPECT_NEAR(third_derivative([](H v) { return v * v * v - 2.0 * v; }, x), 6.0, 1e-14);
  // mixed: f = x^2 y / (1 + y), D^3 f[ex, ex, ey] = 2 d/dy (y / (1 + y)) = 2 / (1 + y)^2
  const double y = 0.4;
  H X = seeded<3>(x, {1.0, 1.0, 0.0}), Y = seeded<3>(y, {0.0, 0.0, 1.0});
  EXPECT_NEAR(mixed_part<3>(X * X * Y / (1.0 + Y)), 2.0 / ((1 + y) * (1 + y)), 1e-14);
  // D^2 f[ex, ey] = 2 x / (1 + y)^2 from the second-order type
  HyperDual<2> X2 = seeded<2>(x, {1.0, 0.0}), Y2 = seeded<2>(y, {0.0, 1.0});
  EXPECT_NEAR(mixed_part<2>(X2 * X2 * Y2 / (1.0 + Y2)), 2 * x / ((1 + y) * (1 + y)), 1e-14);
}

// A problem of two unknowns with a full Jacobian pattern and one parameter.
class TwoUnknowns : public Problem {
 public:
  TwoUnknowns(const char* parameter, double value) {
    params_.add(parameter, value, "the parameter");
    pattern_.resize(2, 2);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) pattern_.insert(i, j) = 0.0;
    pattern_.makeCompressed();
  }
  int size() const override { return 2; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Vector initial_guess() override { return Vector::Zero(2); }

 protected:
  ParameterSet params_;
  SparseMatrix pattern_;
};

// F1 = c2 u1^2 + u2 - lambda, F2 = u2 - d u1^2: on F2 = 0, F1 = (c2 + d) u1^2 - lambda, so the branch
// is lambda = (c2 + d) eps^2 along phi = (1, 0): a fold at the origin with curvature 2 (c2 + d).
class ReducedFold final : public TwoUnknowns {
 public:
  ReducedFold() : TwoUnknowns("lambda", 0.0) {}
  static constexpr double c2 = 1.5, d = 0.7;
  std::string name() const override { return "reduced-fold"; }
  Status residual(const Vector& u, Vector& F) override {
    F.resize(2);
    F[0] = c2 * u[0] * u[0] + u[1] - params_.value(0);
    F[1] = u[1] - d * u[0] * u[0];
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    J.coeffRef(0, 0) = 2 * c2 * u[0];
    J.coeffRef(0, 1) = 1.0;
    J.coeffRef(1, 0) = -2 * d * u[0];
    J.coeffRef(1, 1) = 1.0;
    return {};
  }
};

TEST(NormalForms, FoldCurvatureIsThatOfTheReducedEquation) {
  ReducedFold problem;
  NormalForm nf;
  const Vector u = Vector::Zero(2);
  ASSERT_TRUE(NormalForms().fold(problem, 0, u, nullptr, nf).is_ok());
  // differences of a quadratic: exact up to rounding of the O(1e-4) steps
  EXPECT_NEAR(nf.curvature, 2.0 * (ReducedFold::c2 + ReducedFold::d), 1e-7);
  EXPECT_GT(nf.b, 0.0);
  EXPECT_NEAR(std::abs(nf.phi[0]), 1.0, 1e-12);
  EXPECT_FALSE(nf.exact_derivatives);
  EXPECT_NE(nf.summary().find("minimum"), std::string::npos) << nf.summary();
}

// F1 = k u1 u2 + g u1^3 + mu u1 - lambda, F2 = u2 - d u1^2: on F2 = 0, F1 = (g + k d) u1^3 + mu u1 -
// lambda, a cusp at u = 0, mu = lambda = 0 whose branch at mu = 0 is lambda = (g + k d) eps^3 along
// phi = (1, 0): cubic = -c / (6 b) = g + k d with b = 1 (psi = (-1, 0): F_lambda = (-1, 0)). Both the third
// derivative (g) and the second through h2 = (0, 2 d) (k d) enter; k d alone would be missed by a
// formula without the h2 term.
class ReducedCusp final : public TwoUnknowns {
 public:
  ReducedCusp() : TwoUnknowns("lambda", 0.0) {}
  static constexpr double k = 1.5, d = 0.7, g = -0.4, mu = 0.0;
  std::string name() const override { return "reduced-cusp"; }
  Status residual(const Vector& u, Vector& F) override {
    F.resize(2);
    F[0] = k * u[0] * u[1] + g * u[0] * u[0] * u[0] + mu * u[0] - params_.value(0);
    F[1] = u[1] - d * u[0] * u[0];
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    J.coeffRef(0, 0) = k * u[1] + 3 * g * u[0] * u[0] + mu;
    J.coeffRef(0, 1) = k * u[0];
    J.coeffRef(1, 0) = -2 * d * u[0];
    J.coeffRef(1, 1) = 1.0;
    return {};
  }
};

TEST(NormalForms, CuspCubicCoefficientIsThatOfTheReducedEquation) {
  ReducedCusp problem;
  NormalForm nf;
  ASSERT_TRUE(NormalForms().cusp(problem, 0, Vector::Zero(2), nullptr, nf).is_ok());
  const double cubic = ReducedCusp::g + ReducedCusp::k * ReducedCusp::d;  // 0.65
  // differences of a cubic: third differences at the 1e-2 step exact up to rounding, 1e-7
  EXPECT_EQ(nf.type, "cusp");
  EXPECT_NEAR(nf.b, 1.0, 1e-12);
  EXPECT_NEAR(nf.a, 0.0, 1e-7);
  EXPECT_NEAR(nf.phi[0], 1.0, 1e-12);     // largest entry positive
  EXPECT_NEAR(nf.c, -6.0 * cubic, 1e-6);  // psi = (-1, 0)
  EXPECT_NEAR(nf.cubic, cubic, 1e-7);
}

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
    R = B_ * udot;
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

// The discrete pitchfork at its first branch point lambda_1 = (4 / h^2) sin^2(pi h / 2): u = eps phi
// with phi the grid's sine mode (unit 2-norm), so lambda - lambda_1 = (sum phi_i^4) eps^2 and
// sum_i sin^4(pi i / n) / (sum_i sin^2(pi i / n))^2 = (3 n / 8) / (n / 2)^2 = 3 / (2 n): in the
// amplitude A of u = A sin(pi x), lambda - lambda_1 = 3 A^2 / 4.
TEST(NormalForms, PitchforkCubicCoefficientIsTheGridsClosedForm) {
  for (int n : {16, 40}) {
    const double h = 1.0 / n, lambda1 = 4.0 / (h * h) * std::pow(std::sin(std::numbers::pi * h / 2), 2);
    Pitchfork1DProblem problem(n, lambda1);
    NormalForm nf;
    ASSERT_TRUE(NormalForms().branch_point(problem, 0, Vector::Zero(n - 1), nullptr, nf).is_ok());
    EXPECT_EQ(nf.type, "pitchfork (supercritical)") << nf.summary();
    // differences of a cubic residual: the third derivative to about 1e-8 of its size
    EXPECT_NEAR(nf.cubic, 3.0 / (2.0 * n), 1e-7 * n) << nf.summary();
    EXPECT_EQ(nf.side, 1);
    EXPECT_NEAR(nf.growth_rate_derivative, 1.0, 1e-8);  // sigma = mu_1 - lambda: growth lambda - lambda_1
    // the bifurcating branch's tangent is phi (no parameter part), the trivial one's (0, 1)
    EXPECT_NEAR(nf.tangent_lambda[0], 0.0, 1e-12);
    EXPECT_NEAR(std::abs(nf.tangent_lambda[1]), 1.0, 1e-8);
    EXPECT_NEAR(nf.tangent_u[1].norm(), 0.0, 1e-8);
  }
}

// The Brusselator's uniform Hopf point at b = 1 + a^2: its normal form is that of the ODE
// u' = a - (b + 1) u + u^2 v, v' = b u - u^2 v (the uniform mode's quadratic and cubic terms stay
// uniform), whose first Lyapunov coefficient with q normalised to max |q_i| = 1 (the v entry, since
// |q_v| / |q_u| = sqrt(a^2 + 1) / a > 1) is l1 = -(a^2 + 2) / (2 a (a^2 + 1)) (Kuznetsov's formula
// worked symbolically; the time-dependent form there is x' = f, here B u' = -F with F = -f),
// omega = a, Re d(growth)/db = 1/2 (trace/2 = (b - 1 - a^2) / 2), so the orbit's v amplitude is
// 2 sqrt(|0.5 / Re c1|) sqrt(b - b0).
TEST(NormalForms, BrusselatorHopfAgainstTheClosedForm) {
  for (double a : {2.0, 1.3}) {
    Brusselator1DOptions o;
    o.intervals = 12;
    o.a = a;
    o.b = 1.0 + a * a;
    Brusselator1DProblem problem(o);
    const Vector u = problem.initial_guess();
    NormalForm nf;
    const int b = problem.parameters().index("b");
    ASSERT_TRUE(NormalForms().hopf(problem, b, u, a * 1.01, nullptr, nf).is_ok());
    const double l1 = -(a * a + 2) / (2 * a * (a * a + 1)), re_c1 = l1 * a;
    // differences: the third derivatives to ~1e-8 relative (HigherDerivatives)
    EXPECT_NEAR(nf.omega, a, 1e-10);
    EXPECT_NEAR(nf.l1, l1, 1e-6 * std::abs(l1)) << nf.summary();
    EXPECT_NEAR(nf.growth_rate_derivative, 0.5, 1e-7);
    EXPECT_NEAR(nf.amplitude_coefficient, 2.0 * std::sqrt(0.5 / std::abs(re_c1)), 1e-6);
    EXPECT_EQ(nf.side, 1);
    EXPECT_EQ(nf.type, "Hopf (supercritical)");
    EXPECT_EQ(nf.amplitude_entry % 2, 1);  // a v entry
    EXPECT_NEAR(nf.period, 2 * std::numbers::pi / a, 1e-9);
  }
}

// The Brusselator ODE in curved coordinates: x = x0 + y + g(y) with g quadratic (g(0) = 0, Dg(0) =
// 0) turns x' = f(x) into (I + Dg(y)) y' = f(x0 + y + g(y)): the same orbits, with a mass matrix
// B(y) = I + Dg(y) that depends on the state, as the collapsible channel's moving wall does. Its
// normal form is the original one (q and p are unchanged at y = 0, and the B'(y)[.] y' terms
// of D^2 R and D^3 R make up for the curvature), and so are the orbit amplitudes of x.
class CurvedBrusselator final : public TwoUnknowns {
 public:
  static constexpr double a = 2.0, g1 = 0.7, g2 = -1.3, g3 = 0.4;
  CurvedBrusselator() : TwoUnknowns("b", 1.0 + a * a) {}
  std::string name() const override { return "curved-brusselator"; }
  // x = x0(b) + y + g(y), g = (g1 y0 y1 + g3 y1^2, g2 y0^2)
  Vector x_of(const Vector& y) const {
    const double b = params_.value(0);
    Vector x(2);
    x << a + y[0] + g1 * y[0] * y[1] + g3 * y[1] * y[1], b / a + y[1] + g2 * y[0] * y[0];
    return x;
  }
  Eigen::Matrix2d Dg(const Vector& y) const {
    Eigen::Matrix2d m;
    m << 1.0 + g1 * y[1], g1 * y[0] + 2 * g3 * y[1], 2 * g2 * y[0], 1.0;
    return m;
  }
  Status residual(const Vector& y, Vector& F) override {
    const double b = params_.value(0);
    const Vector x = x_of(y);
    F.resize(2);
    F[0] = -(a - (b + 1) * x[0] + x[0] * x[0] * x[1]);
    F[1] = -(b * x[0] - x[0] * x[0] * x[1]);
    return {};
  }
  Status jacobian(const Vector& y, Vector& F, SparseMatrix& J) override {
    residual(y, F);
    const double b = params_.value(0);
    const Vector x = x_of(y);
    Eigen::Matrix2d fx;
    fx << -(b + 1) + 2 * x[0] * x[1], x[0] * x[0], b - 2 * x[0] * x[1], -x[0] * x[0];
    const Eigen::Matrix2d m = -fx * Dg(y);
    J = pattern_;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) J.coeffRef(i, j) = m(i, j);
    return {};
  }
  Status mass_matrix(const Vector& y, SparseMatrix& B) override {
    B = pattern_;  // callers may pass any matrix (has_time_form an empty one)
    const Eigen::Matrix2d m = Dg(y);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) B.coeffRef(i, j) = m(i, j);
    return {};
  }
  Status time_residual(const Vector& y, const Vector& ydot, Vector& R) override {
    const Eigen::Matrix2d m = Dg(y);
    R.resize(2);
    R[0] = m(0, 0) * ydot[0] + m(0, 1) * ydot[1];
    R[1] = m(1, 0) * ydot[0] + m(1, 1) * ydot[1];
    return {};
  }
  std::vector<std::string> observable_names() const override { return {"x_u", "x_v"}; }
  Status observables(const Vector& y, std::vector<double>& values) override {
    const Vector x = x_of(y);
    values = {x[0], x[1]};
    return {};
  }
};

TEST(NormalForms, AStateDependentMassMatrixKeepsTheNormalFormOfTheOriginalCoordinates) {
  CurvedBrusselator problem;
  NormalForm nf;
  ASSERT_TRUE(NormalForms().hopf(problem, 0, Vector::Zero(2), 2.0, nullptr, nf).is_ok());
  const double l1 = -(CurvedBrusselator::a * CurvedBrusselator::a + 2) /
                    (2 * CurvedBrusselator::a * (CurvedBrusselator::a * CurvedBrusselator::a + 1));
  const double v_amplitude = 2.0 * std::sqrt(0.5 / std::abs(l1 * CurvedBrusselator::a));
  // differences of a residual of degree 6: the truncation error of D^3 at its step 1e-2 is ~1e-3
  // relative (measured 8e-4 in l1; 8e-6 with steps ten times smaller). Without the B'(y)[.] y' terms
  // the amplitude comes out 0.536 instead of 1.826 (measured with them left out).
  EXPECT_NEAR(nf.omega, 2.0, 1e-10);
  EXPECT_NEAR(nf.l1, l1, 2e-3 * std::abs(l1)) << nf.summary();
  ASSERT_EQ(nf.observable_amplitudes.size(), 2u);
  EXPECT_NEAR(nf.observable_amplitudes[1], v_amplitude, 2e-3 * v_amplitude);
}

// At a Hopf point the solve with J + 2 i omega B (h20) runs by GMRES on the factorisation of J +
// i omega B that q and p need, deflated of the critical mode (NormalFormSolvers.hpp:
// DeflatedShiftSolver): two factorisations (that and J's) instead of three, and the same
// coefficients as with a factorisation of its own (GMRES's residual 1e-12, the direct solves'
// rounding: agreement to 1e-9 relative). A GMRES that does not converge in its allowance (here one
// iteration, where the right-hand side is no eigenvector of the preconditioned operator) hands the
// solve to a factorisation: the same numbers again. On the Brusselator in 1D (many modes, the
// uniform one critical) and on its curved form (a state-dependent B).
TEST(NormalForms, HopfSolvesOnTheFactorisationAtOmegaAgreeWithFactorisationsOfTheirOwn) {
  Brusselator1DOptions o;
  o.intervals = 40;
  o.a = 2.0;
  o.b = 5.0;
  Brusselator1DProblem brusselator(o);
  CurvedBrusselator curved;
  for (Problem* problem : std::vector<Problem*>{&brusselator, &curved}) {
    const Vector u = problem == &curved ? Vector::Zero(2) : brusselator.initial_guess();
    const int b = problem->parameters().index("b");
    NormalForm krylov, direct, fallback;
    ASSERT_TRUE(NormalForms().hopf(*problem, b, u, 2.02, nullptr, krylov).is_ok());
    ASSERT_TRUE(NormalForms({}, false, 0).hopf(*problem, b, u, 2.02, nullptr, direct).is_ok());
    ASSERT_TRUE(NormalForms({}, false, 1).hopf(*problem, b, u, 2.02, nullptr, fallback).is_ok());
    EXPECT_EQ(krylov.factorisations, 2) << problem->name();
    EXPECT_GE(krylov.gmres_iterations, 2) << problem->name();
    EXPECT_EQ(direct.factorisations, 3) << problem->name();
    EXPECT_EQ(direct.gmres_iterations, 0) << problem->name();
    EXPECT_EQ(fallback.factorisations, 3) << problem->name();
    for (const NormalForm* nf : {&krylov, &fallback}) {
      EXPECT_NEAR(nf->l1, direct.l1, 1e-9 * std::abs(direct.l1)) << problem->name();
      EXPECT_NEAR(nf->growth_rate_derivative, direct.growth_rate_derivative,
                  1e-9 * std::abs(direct.growth_rate_derivative))
          << problem->name();
      EXPECT_NEAR(std::abs(nf->c1 - direct.c1), 0.0, 1e-9 * std::abs(direct.c1)) << problem->name();
    }
  }
}

// The collapsible channel's kernels (flow with inertia and shape derivatives, FENE-P conformation,
// mesh, solid): second and third derivatives by hyper-dual numbers against central differences of
// its residual at a converged steady state, along smooth directions (the branch's derivatives in
// Wi, Re and Pe) with a change of Wi in one of them. The differences converge to the exact values
// at second order: halving the step cuts their error fourfold (measured 4.00 and 4.06; the errors
// 6e-5 and 2e-3 of the derivatives); a wrong hyper-dual derivative would leave an error of its own
// size that does not shrink.
TEST(NormalForms, ExactDerivativesOfTheCollapsibleChannelAreTheLimitOfDifferences) {
  CollapsibleOptions o;
  o.mesh = test::custom_channel_mesh(2, 4, 2, 2, 1);
  o.Pe = 0.04;
  o.fluid.model = FluidModel::FeneP;
  o.fluid.Wi = 0.3;
  o.fluid.beta = 0.5;
  o.fluid.constants.b = 20.0;
  o.fluid.Re = 1.0;
  o.fluid.inertia = true;
  o.fluid.profile = ProfileKind::FullyDeveloped;
  CollapsibleChannelProblem problem(o);
  Vector u = problem.initial_guess();
  NewtonSolver newton(problem);
  ASSERT_TRUE(newton.solve(u).converged());
  ParameterSet& params = problem.parameters();
  const int wi = params.index("Wi");
  auto along = [&](const char* name, double dv) {  // du/dp along the branch
    const int i = params.index(name);
    const double v = params.value(i);
    Vector w = u;
    params.set(i, v + dv);
    EXPECT_TRUE(newton.solve(w).converged());
    params.set(i, v);
    return Vector((w - u) / dv);
  };
  const Vector a = along("Wi", 0.01), b = along("Re", 0.1), c = along("Pe", 0.004);
  const double b_wi = 0.3;  // b also changes Wi
  HigherDerivatives exact(problem, wi, u);
  ASSERT_EQ(exact.method(), HigherDerivatives::Method::Exact);
  Vector e2, e3;
  ASSERT_TRUE(exact.second({a}, {b, b_wi}, e2).is_ok());
  ASSERT_TRUE(exact.third({a}, {b, b_wi}, {c}, e3).is_ok());
  // F at u + s_a a + s_b b + s_c c, Wi + s_b b_wi
  auto F = [&](double sa, double sb, double sc) {
    Vector r;
    params.set(wi, 0.3 + sb * b_wi);
    EXPECT_TRUE(problem.residual(u + sa * a + sb * b + sc * c, r).is_ok());
    params.set(wi, 0.3);
    return r;
  };
  auto d2 = [&](double h) { return Vector((F(h, h, 0) - F(h, -h, 0) - F(-h, h, 0) + F(-h, -h, 0)) / (4 * h * h)); };
  auto d3 = [&](double h) {
    Vector s = Vector::Zero(u.size());
    for (int k = 0; k < 8; ++k) {
      const double x = k & 1 ? -h : h, y = k & 2 ? -h : h, z = k & 4 ? -h : h;
      s += (x * y * z > 0 ? 1.0 : -1.0) * F(x, y, z);
    }
    return Vector(s / (8 * h * h * h));
  };
  // steps in the truncation regime (rounding, eps x the size of the terms assembled over h^2 or h^3,
  // takes over below about 0.03 and 0.2 of the directions' largest entries)
  const double h2 = 0.4 / a.lpNorm<Eigen::Infinity>(), h3 = 0.8 / c.lpNorm<Eigen::Infinity>();
  const double err2 = (d2(h2) - e2).norm(), err2_half = (d2(h2 / 2) - e2).norm();
  const double err3 = (d3(h3) - e3).norm(), err3_half = (d3(h3 / 2) - e3).norm();
  RecordProperty("D2_ratio", std::to_string(err2 / err2_half));
  RecordProperty("D3_ratio", std::to_string(err3 / err3_half));
  EXPECT_GT(e2.norm(), 0.0);
  EXPECT_GT(e3.norm(), 0.0);
  EXPECT_NEAR(err2 / err2_half, 4.0, 0.5);
  EXPECT_NEAR(err3 / err3_half, 4.0, 0.5);
  EXPECT_LT(err2_half, 1e-3 * e2.norm());
  EXPECT_LT(err3_half, 1e-2 * e3.norm());
  // symmetric in the directions
  Vector e2ba;
  ASSERT_TRUE(exact.second({b, b_wi}, {a}, e2ba).is_ok());
  EXPECT_LT((e2ba - e2).norm(), 1e-12 * e2.norm());
}

}  // namespace
