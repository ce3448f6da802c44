// Normal forms of located points against closed forms (stability/NormalForms.hpp): a fold's
// curvature and a cusp's cubic coefficient from problems with known reduced equations, the discrete
// pitchfork's cubic coefficient, the Brusselator's first Lyapunov coefficient, frequency,
// transversality and orbit amplitude (and h20 by GMRES against a factorisation of its own); and the
// derivatives they are built on: hyper-dual numbers against closed-form derivatives, and the exact
// (hyper-dual) derivatives of the collapsible channel's kernels against central differences of its
// residual. Bogdanov-Takens and fold-Hopf points: CodimTwoNormalFormsTest.cpp.
#include <gtest/gtest.h>

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
#include "support/ExactBrusselator.hpp"
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

// Complex derivatives are expanded in real ones, each distinct one evaluated once per
// HigherDerivatives object: D^2 R[Q, conj Q] with Q = (q, i omega q) on the curved Brusselator (by
// differences, B depends on the state) has the real directions a = Re Q and b = Im Q: F's part on
// the multisets {a,a}, {a,b}, {b,b} (4 residuals each) and the time terms' B'[x] r for r, x in {a,
// b} (2 each): 20 evaluations, where a sum over the multisets would take 24; D^2 R[Q, Q] after it
// takes none, and equals what a fresh object computes. The real derivatives share the cache: after
// D^2 R[Q, Q] the real D^2[a,a], D^2[b,b] and D^2[a,b] cost nothing, and the expansion D^2[a,a] -
// D^2[b,b] + 2i D^2[a,b] gives D^2 R[Q, Q] (the signs and factors i of the complex expansion; 1e-12).
TEST(HigherDerivatives, ComplexDerivativesEvaluateEachRealPartOnce) {
  CurvedBrusselator problem;
  const double omega = 2.0;
  Eigen::VectorXcd q(2);
  q << 1.0, std::complex<double>(0.3, 0.7);
  const std::complex<double> I(0.0, 1.0);
  using CD = HigherDerivatives::ComplexDirection;
  const CD Q{q, 0.0, I * omega * q}, Qbar{q.conjugate(), 0.0, -I * omega * q.conjugate()};
  HigherDerivatives d(problem, 0, Vector::Zero(2));
  Eigen::VectorXcd mixed, square, fresh_square;
  ASSERT_TRUE(d.second(Q, Qbar, mixed).is_ok());
  EXPECT_EQ(d.evaluations(), 20);
  ASSERT_TRUE(d.second(Q, Q, square).is_ok());
  EXPECT_EQ(d.evaluations(), 20);
  HigherDerivatives fresh(problem, 0, Vector::Zero(2));
  ASSERT_TRUE(fresh.second(Q, Q, fresh_square).is_ok());
  EXPECT_NEAR((square - fresh_square).norm(), 0.0, 1e-14 * square.norm());
  const HigherDerivatives::Direction a{q.real(), 0.0, (I * omega * q).real()}, b{q.imag(), 0.0, (I * omega * q).imag()};
  Vector aa, bb, ab;
  const long evaluations = fresh.evaluations();
  ASSERT_TRUE(fresh.second(a, a, aa).is_ok() && fresh.second(b, b, bb).is_ok() && fresh.second(a, b, ab).is_ok());
  EXPECT_EQ(fresh.evaluations(), evaluations);
  const Eigen::VectorXcd expected = (aa - bb).cast<std::complex<double>>() + 2.0 * I * ab.cast<std::complex<double>>();
  EXPECT_NEAR((square - expected).norm(), 0.0, 1e-12 * expected.norm());
  EXPECT_NEAR((mixed - (aa + bb).cast<std::complex<double>>()).norm(), 0.0, 1e-12 * mixed.norm());
}

// A Hopf point's solves with J + i s B, three ways (NormalFormSolvers.hpp):
// - by default, GMRES preconditioned by J's real factorisation (RealLUShiftSolver): q and p from
//   bordered systems, omega by rounds of the Rayleigh quotient, h20 by GMRES: one factorisation;
// - where that does not converge in the allowance (4 iterations on the Brusselator in 1D, whose
//   diffusive modes spread the preconditioned spectrum: its solves take 10), q and p on the complex
//   factorisation at omega and h20 by GMRES on it, deflated of the critical mode
//   (DeflatedShiftSolver): two;
// - allowance 0: every solve on a factorisation of its own: three.
// The coefficients agree to the accuracy of the solves where the derivatives are exact: the 1D
// Brusselator with its exact derivatives (support/ExactBrusselator.hpp), whose l1 is -0.3 in
// closed form; measured agreement 1.5e-10 relative in l1 at worst over OpenBLAS's Prescott,
// Haswell, SkylakeX and Zen kernels (q agrees to 1.6e-12). With difference derivatives the
// rounding of D^3 (eps S / h^3, S the diffusion terms) is 1e-9 of l1 and a different draw for q's
// that differ by rounding: measured 1.1e-9 apart with the Prescott kernels. The curved Brusselator
// has difference derivatives: the rate part of its third derivatives is a mixed difference at the
// step 1e-4 (eps / (2e-4)^2 = 6e-9 per term; measured up to 1.5e-8 in c1 and 1e-8 in l1 over
// the same kernels): 5e-8.
// On the curved form B depends on the state, and its 2 unknowns let each bordered solve converge
// in 3 iterations. Every solve is at the given state: the problem's initial guess is not asked for
// (it throws here, as a problem's may where no guess exists at the present parameters).
TEST(NormalForms, HopfSolvesOnJsFactorisationAgreeWithComplexFactorisations) {
  Brusselator1DOptions o;
  o.intervals = 40;
  o.a = 2.0;
  o.b = 5.0;
  test::ExactBrusselator brusselator(o);
  const Vector uniform = brusselator.initial_guess();
  brusselator.guess_throws = true;  // the solves and derivatives are at the given state alone
  CurvedBrusselator curved;
  for (Problem* problem : std::vector<Problem*>{&brusselator, &curved}) {
    const bool flat = problem == &brusselator;
    const Vector u = flat ? uniform : Vector::Zero(2);
    const int b = problem->parameters().index("b");
    NormalForm on_j, direct, deflated, fallback;
    ASSERT_TRUE(NormalForms().hopf(*problem, b, u, 2.02, nullptr, on_j).is_ok());
    ASSERT_TRUE(NormalForms({}, false, 0).hopf(*problem, b, u, 2.02, nullptr, direct).is_ok());
    ASSERT_TRUE(NormalForms({}, false, 1).hopf(*problem, b, u, 2.02, nullptr, fallback).is_ok());
    EXPECT_EQ(on_j.factorisations, 1) << problem->name();
    EXPECT_GE(on_j.gmres_iterations, 6) << problem->name();
    EXPECT_EQ(direct.factorisations, 3) << problem->name();
    EXPECT_EQ(direct.gmres_iterations, 0) << problem->name();
    EXPECT_EQ(fallback.factorisations, 3) << problem->name();
    std::vector<const NormalForm*> others{&on_j, &fallback};
    if (flat) {
      ASSERT_TRUE(NormalForms({}, false, 4).hopf(*problem, b, u, 2.02, nullptr, deflated).is_ok());
      EXPECT_EQ(deflated.factorisations, 2);
      EXPECT_GE(deflated.gmres_iterations, 2);
      others.push_back(&deflated);
    }
    const double tol = flat ? 1e-9 : 5e-8;
    if (flat) {  // the exact derivatives: l1 of the closed form (BrusselatorHopfAgainstTheClosedForm)
      EXPECT_NEAR(direct.l1, -0.3, tol * 0.3);
      EXPECT_TRUE(direct.exact_derivatives);
    }
    for (const NormalForm* nf : others) {
      EXPECT_NEAR(nf->omega, direct.omega, 1e-12 * direct.omega) << problem->name();
      EXPECT_NEAR(nf->l1, direct.l1, tol * std::abs(direct.l1)) << problem->name();
      EXPECT_NEAR(nf->growth_rate_derivative, direct.growth_rate_derivative,
                  tol * std::abs(direct.growth_rate_derivative))
          << problem->name();
      EXPECT_NEAR(std::abs(nf->c1 - direct.c1), 0.0, tol * std::abs(direct.c1)) << problem->name();
      EXPECT_NEAR((nf->q - direct.q).norm(), 0.0, 1e-9) << problem->name();
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
