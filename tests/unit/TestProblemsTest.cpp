// The algebraic test problems for stability and bifurcation work (pitchfork1d, brusselator1d):
// analytic Jacobians and parameter derivatives against central differences, their mass
// matrices, and the known linear spectra: branch points of the trivial pitchfork branch at the
// discrete Laplacian's eigenvalues, the Hopf pair of the uniform Brusselator state at
// b = 1 + a^2 with frequency a.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>

#include "continuation/Continuation.hpp"
#include "core/Scene.hpp"
#include "problems/analytic/Brusselator1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "support/TestProblems.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

constexpr double kPi = std::numbers::pi;

// Jacobian and parameter-derivative tolerance: central differences with step 1e-7 (Jacobian)
// and 1e-6 (parameters), relative to the largest entry of each row (Jacobian) or of the vector
// (dF/dp), have truncation error O(h^2) ~ 1e-14 for these polynomial residuals and rounding
// error ~ 1e-16 |F| / h ~ 1e-9 (|F| is at most the row's largest entry times |u| here), so 1e-7
// leaves two orders of margin and still catches any wrong term (those give errors of order 1).
constexpr double kFdTolerance = 1e-7;

Eigen::MatrixXd dense(const SparseMatrix& A) { return Eigen::MatrixXd(A); }

// Dense generalised eigenvalues sigma of J phi = sigma B phi for a nonsingular B, as the
// eigenvalues of B^{-1} J by Francis QR. Not Eigen 3.4's QZ (GeneralizedEigenSolver): on these
// Brusselator matrices its RealQZ exceeds its default 400 iterations per eigenvalue (a = 1.3,
// b = 1 + a^2 +- 1e-3, n = 50), and then eigenvalues() returns uninitialised memory under NDEBUG.
Eigen::VectorXcd generalized_eigenvalues(const SparseMatrix& J, const SparseMatrix& B) {
  const Eigen::MatrixXd A = Eigen::PartialPivLU<Eigen::MatrixXd>(dense(B)).solve(dense(J));
  Eigen::EigenSolver<Eigen::MatrixXd> es(A, false);
  EXPECT_EQ(es.info(), Eigen::Success);
  return es.eigenvalues();
}

// A nonuniform pitchfork state with all modes present and no symmetry.
Vector pitchfork_state(const Pitchfork1DProblem& p) {
  Vector u(p.size());
  for (int i = 0; i < p.size(); ++i) {
    const double x = (i + 1) * p.h();
    u[i] = 0.7 * std::sin(kPi * x) + 0.3 * std::sin(3 * kPi * x) + 0.25 * x * (1 - x) * std::exp(x);
  }
  return u;
}

Brusselator1DOptions brusselator_options(int n, double b) {
  Brusselator1DOptions o;
  o.intervals = n;
  o.length = 1.7;
  o.a = 2.0;
  o.b = b;
  o.D_u = 0.8;
  o.D_v = 1.3;
  return o;
}

// A nonuniform Brusselator state (u, v) with nonzero slopes at the no-flux ends (so the ghost
// rows are exercised with an asymmetric neighbourhood).
Vector brusselator_state(const Brusselator1DProblem& p) {
  Vector w(p.size());
  for (int i = 0; i <= p.intervals(); ++i) {
    const double x = i * p.h();
    w[2 * i] = 2.0 + 0.4 * std::cos(2.0 * x) + 0.3 * x * x;
    w[2 * i + 1] = 1.5 - 0.5 * std::sin(3.0 * x) + 0.2 * x;
  }
  return w;
}

}  // namespace

TEST(Pitchfork1D, JacobianAndParameterDerivativesMatchCentralDifferences) {
  Pitchfork1DProblem p(40, 12.3, 0.05);
  const Vector u = pitchfork_state(p);
  const auto jc = test::check_problem_jacobian(p, u);
  const double dl = test::check_parameter_derivative(p, 0, u), de = test::check_parameter_derivative(p, 1, u);
  std::cout << "pitchfork1d: J max rel error " << jc.max_relative_error << " (row " << jc.worst_row << ", col "
            << jc.worst_col << "), dF/dlambda " << dl << ", dF/deps " << de << "\n";
  EXPECT_LT(jc.max_relative_error, kFdTolerance);
  EXPECT_LT(dl, kFdTolerance);
  EXPECT_LT(de, kFdTolerance);
  // the Jacobian fills exactly its declared pattern
  Vector F;
  SparseMatrix J = p.jacobian_pattern();
  ASSERT_TRUE(p.jacobian(u, F, J).is_ok());
  EXPECT_EQ(J.nonZeros(), p.jacobian_pattern().nonZeros());
}

// B du/dt = -F with F = -(u'' + lambda u - u^3 + eps) at the interior nodes: B = I exactly,
// with the Jacobian's structure.
TEST(Pitchfork1D, MassMatrixIsTheIdentity) {
  Pitchfork1DProblem p(40, 3.0);
  const Vector u = pitchfork_state(p);
  SparseMatrix B = p.jacobian_pattern();
  ASSERT_TRUE(p.mass_matrix(u, B).is_ok());
  EXPECT_EQ(B.nonZeros(), p.jacobian_pattern().nonZeros());
  EXPECT_EQ((dense(B) - Eigen::MatrixXd::Identity(p.size(), p.size())).cwiseAbs().maxCoeff(), 0.0);
}

// J on u = 0 is tridiag(-1, 2, -1) / h^2 - lambda: its smallest eigenvalue vanishes exactly at
// the discrete lambda_1 = (4 / h^2) sin^2(pi h / 2), with eigenvector sin(pi x); lambda_2 is the
// next zero. Entries are ~ 4 / h^2 = 1e4, so rounding in the eigenvalues is ~ 1e-12: 1e-10.
TEST(Pitchfork1D, TrivialBranchLosesStabilityAtTheDiscreteEigenvalues) {
  const int n = 50;
  const double h = 1.0 / n;
  const double l1 = Pitchfork1DProblem::branch_point(1, n), l2 = Pitchfork1DProblem::branch_point(2, n);
  EXPECT_DOUBLE_EQ(l1, 4.0 / (h * h) * std::pow(std::sin(kPi * h / 2), 2));
  EXPECT_NEAR(l1, kPi * kPi, kPi * kPi * kPi * kPi * h * h / 12 * 1.01);  // O(h^2) below pi^2
  EXPECT_LT(l1, kPi * kPi);
  for (double lambda : {l1, l2}) {
    Pitchfork1DProblem p(n, lambda);
    const Vector u = p.initial_guess();
    Vector F;
    SparseMatrix J = p.jacobian_pattern();
    ASSERT_TRUE(p.jacobian(u, F, J).is_ok());
    EXPECT_EQ(F.cwiseAbs().maxCoeff(), 0.0);  // u = 0 solves F = 0 exactly for eps = 0
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(dense(J));
    const Vector sigma = es.eigenvalues();  // ascending
    const int k = lambda == l1 ? 0 : 1;     // the zero eigenvalue is the (k+1)-th smallest
    std::cout << "pitchfork1d n = 50 at lambda_" << k + 1 << " = " << lambda << ": sigma = " << sigma[k] << " (next "
              << sigma[k + 1] << ")\n";
    EXPECT_NEAR(sigma[k], 0.0, 1e-10);
    for (int j = 0; j < k; ++j) EXPECT_LT(sigma[j], -1.0);  // the modes already unstable
    EXPECT_GT(sigma[k + 1], 1.0);
    // the null vector is the grid function sin((k + 1) pi x)
    Vector mode(p.size());
    for (int i = 0; i < p.size(); ++i) mode[i] = std::sin((k + 1) * kPi * (i + 1) * h);
    const Vector phi = es.eigenvectors().col(k);
    EXPECT_NEAR(std::abs(phi.dot(mode)) / mode.norm(), 1.0, 1e-12);
  }
  // below lambda_1 every sigma > 0 (u = 0 stable), just above it exactly one is negative
  for (double lambda : {l1 - 1e-3, l1 + 1e-3}) {
    Pitchfork1DProblem p(n, lambda);
    Vector F;
    SparseMatrix J = p.jacobian_pattern();
    ASSERT_TRUE(p.jacobian(p.initial_guess(), F, J).is_ok());
    const Vector sigma = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense(J)).eigenvalues();
    EXPECT_EQ((sigma.array() < 0).count(), lambda < l1 ? 0 : 1);
  }
}

// The continuation engine sees both branch points of the trivial branch where the spectrum says.
TEST(Pitchfork1D, ContinuationLocatesTheBranchPointsOfTheTrivialBranch) {
  const int n = 50;
  Pitchfork1DProblem p(n, 1.0);
  const ContinuationOptions o = test::pitchfork_trivial_options();
  Continuation cont(p, o);
  test::RecordingObserver rec;
  const auto r = cont.run(p.initial_guess(), rec);
  EXPECT_EQ(r.code, StopCode::UpperBound) << r.reason;
  const auto bps = rec.of_kind(PointKind::BranchPoint);
  ASSERT_EQ(bps.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    std::cout << std::setprecision(13) << "pitchfork1d: branch point " << k + 1
              << " located at lambda = " << bps[k]->lambda << " (exact " << Pitchfork1DProblem::branch_point(k + 1, n)
              << ")\n";
    // located to event_tolerance in the parameter; the bisection's last bracket may be 10x that
    EXPECT_NEAR(bps[k]->lambda, Pitchfork1DProblem::branch_point(k + 1, n), 1e-8);
    EXPECT_LT(bps[k]->u.cwiseAbs().maxCoeff(), 1e-12);  // still on u = 0
  }
}

TEST(Pitchfork1D, ObservablesOnAKnownProfile) {
  // u_i = sin(2 pi x_i): u(1/2) = 0, u(1/4) = 1, discrete L2 norm sqrt(h sum sin^2) = sqrt(1/2)
  Pitchfork1DProblem p(64, 1.0);
  Vector u(p.size());
  for (int i = 0; i < p.size(); ++i) u[i] = std::sin(2 * kPi * (i + 1) * p.h());
  std::vector<double> v;
  ASSERT_TRUE(p.observables(u, v).is_ok());
  ASSERT_EQ(v.size(), p.observable_names().size());
  EXPECT_NEAR(v[0], 0.0, 1e-15);
  EXPECT_NEAR(v[1], 1.0, 1e-15);
  EXPECT_NEAR(v[2], std::sqrt(0.5), 1e-14);
  EXPECT_NEAR(v[3], 1.0, 1e-15);
  // odd n: u(1/2) interpolated between the two middle nodes
  Pitchfork1DProblem q(5, 1.0);
  Vector w(4);
  w << 1.0, 2.0, 4.0, 3.0;
  ASSERT_TRUE(q.observables(w, v).is_ok());
  EXPECT_DOUBLE_EQ(v[0], 3.0);
  EXPECT_DOUBLE_EQ(v[1], 1.25);  // x = 1/4 lies at 1.25 h: between nodes 1 (u = 1) and 2 (u = 2)
}

TEST(Brusselator1D, JacobianAndParameterDerivativesMatchCentralDifferences) {
  Brusselator1DProblem p(brusselator_options(30, 4.1));
  const Vector w = brusselator_state(p);
  const auto jc = test::check_problem_jacobian(p, w);
  std::cout << "brusselator1d: J max rel error " << jc.max_relative_error << " (row " << jc.worst_row << ", col "
            << jc.worst_col << ")";
  EXPECT_LT(jc.max_relative_error, kFdTolerance);
  for (const char* name : {"a", "b", "D_u", "D_v"}) {
    const double e = test::check_parameter_derivative(p, p.parameters().index(name), w);
    std::cout << ", dF/d" << name << " " << e;
    EXPECT_LT(e, kFdTolerance) << name;
  }
  std::cout << "\n";
  Vector F;
  SparseMatrix J = p.jacobian_pattern();
  ASSERT_TRUE(p.jacobian(w, F, J).is_ok());
  EXPECT_EQ(J.nonZeros(), p.jacobian_pattern().nonZeros());
}

// Nodal finite differences with ghost points: B = I. What makes that the right B is that the
// scheme conserves like the PDE: with the trapezoidal weights q (h/2 at the ends, h inside),
// q^T Laplacian = 0 exactly, so d/dt sum q (u + v) = -q^T (F_u + F_v) = sum q (a - u), the
// discrete form of d/dt int (u + v) dx = int (a - u) dx with no flux through the ends.
TEST(Brusselator1D, MassMatrixIsTheIdentityAndTheSchemeConserves) {
  Brusselator1DProblem p(brusselator_options(30, 4.1));
  const Vector w = brusselator_state(p);
  SparseMatrix B = p.jacobian_pattern();
  ASSERT_TRUE(p.mass_matrix(w, B).is_ok());
  EXPECT_EQ(B.nonZeros(), p.jacobian_pattern().nonZeros());
  EXPECT_EQ((dense(B) - Eigen::MatrixXd::Identity(p.size(), p.size())).cwiseAbs().maxCoeff(), 0.0);
  Vector F;
  ASSERT_TRUE(p.residual(w, F).is_ok());
  const int n = p.intervals();
  const double a = p.parameters().get("a");
  double lhs = 0, rhs = 0, scale = 0;
  for (int i = 0; i <= n; ++i) {
    const double q = (i == 0 || i == n) ? 0.5 * p.h() : p.h();
    lhs += -q * (F[2 * i] + F[2 * i + 1]);
    rhs += q * (a - w[2 * i]);
    scale += q * (std::abs(F[2 * i]) + std::abs(F[2 * i + 1]));
  }
  std::cout << "brusselator1d: conservation defect " << std::abs(lhs - rhs) << " against " << scale << "\n";
  EXPECT_LT(std::abs(lhs - rhs), 1e-13 * scale);
}

// The uniform state (a, b / a) solves F = 0 to rounding (entries a, (b + 1) a, a^2 (b / a) ~ 10:
// 1e-12 is a few hundred ulps), for any parameters.
TEST(Brusselator1D, UniformStateIsAnExactSolution) {
  for (double b : {0.5, 3.0, 5.0, 7.3}) {
    Brusselator1DProblem p(brusselator_options(50, b));
    Vector F;
    ASSERT_TRUE(p.residual(p.initial_guess(), F).is_ok());
    EXPECT_LT(F.cwiseAbs().maxCoeff(), 1e-12) << "b = " << b;
    std::vector<double> v;
    ASSERT_TRUE(p.observables(p.initial_guess(), v).is_ok());
    EXPECT_NEAR(v[0], 2.0, 1e-14);
    EXPECT_NEAR(v[1], b / 2.0, 1e-14);
  }
}

// J phi = sigma B phi on the uniform state: at b = 1 + a^2 the k = 0 mode has sigma = +-i a
// (growth rate -sigma: neutral, frequency a); every other eigenvalue has Re sigma > 0. Just
// below every Re sigma > 0, just above exactly the pair has Re sigma < 0. Entries of J are
// ~ 2 D / h^2 ~ 2e3 here, so rounding in the eigenvalues of this well-conditioned pair is
// ~ 1e-12: 1e-10.
TEST(Brusselator1D, UniformStateHasItsHopfPairAtBEqualOnePlusASquared) {
  for (double a : {2.0, 1.3}) {
    for (bool equal_diffusion : {true, false}) {
      Brusselator1DOptions o = brusselator_options(50, 1.0 + a * a);
      o.a = a;
      if (equal_diffusion) o.D_u = o.D_v = 1.0;
      Brusselator1DProblem p(o);
      const Vector w = p.initial_guess();
      Vector F;
      SparseMatrix J = p.jacobian_pattern(), B = p.jacobian_pattern();
      ASSERT_TRUE(p.jacobian(w, F, J).is_ok());
      ASSERT_TRUE(p.mass_matrix(w, B).is_ok());
      const Eigen::VectorXcd sigma = generalized_eigenvalues(J, B);
      // the pair: the two eigenvalues of smallest real part
      std::vector<std::complex<double>> s(sigma.data(), sigma.data() + sigma.size());
      std::sort(s.begin(), s.end(), [](auto x, auto y) { return x.real() < y.real(); });
      std::cout << "brusselator1d a = " << a << (equal_diffusion ? ", D_u = D_v" : ", D_u != D_v")
                << " at b = 1 + a^2: sigma = " << s[0] << ", " << s[1] << " (|Im| - a: " << std::abs(s[0].imag()) - a
                << ", " << std::abs(s[1].imag()) - a << "); next Re sigma " << s[2].real() << "\n";
      for (int k = 0; k < 2; ++k) {
        EXPECT_NEAR(s[k].real(), 0.0, 1e-10);
        EXPECT_NEAR(std::abs(s[k].imag()), a, 1e-10);
      }
      EXPECT_NEAR(s[0].imag() + s[1].imag(), 0.0, 1e-10);
      // with these diffusivities (and L = 1.7) the other modes are damped
      EXPECT_GT(s[2].real(), 0.1);
      for (double db : {-1e-3, 1e-3}) {
        p.parameters().set("b", 1.0 + a * a + db);
        ASSERT_TRUE(p.jacobian(p.initial_guess(), F, J).is_ok());
        const Eigen::VectorXcd sg = generalized_eigenvalues(J, B);
        EXPECT_EQ((sg.real().array() < 0).count(), db < 0 ? 0 : 2) << "b - (1 + a^2) = " << db;
      }
    }
  }
}

TEST(TestProblemScenes, KeysAreValidated) {
  SceneSchema ps, bs;
  Pitchfork1DProblem::declare(ps);
  Brusselator1DOptions::declare(bs);
  EXPECT_THROW(Scene::parse("[pitchfork]\nintervals = 1\n", "s.toml", ps), SceneError);
  EXPECT_THROW(Scene::parse("[brusselator]\nlength = 0\n", "s.toml", bs), SceneError);
  EXPECT_THROW(Scene::parse("[parameters]\na = 0\n", "s.toml", bs), SceneError);
  const auto pp = Pitchfork1DProblem::from_scene(Scene::parse("[parameters]\neps = 0.1\n", "s.toml", ps));
  EXPECT_EQ(pp->size(), 63);
  EXPECT_EQ(pp->parameters().get("eps"), 0.1);
  const auto bp = Brusselator1DProblem::from_scene(Scene::parse("[brusselator]\nintervals = 10\n", "s.toml", bs));
  EXPECT_EQ(bp->size(), 22);
  EXPECT_EQ(bp->parameters().get("a"), 2.0);
  EXPECT_EQ(bp->parameters().get("D_u"), bp->parameters().get("D_v"));
}
