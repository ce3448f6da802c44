// Periodic orbits by shooting (continuation/orbits) and their Floquet multipliers
// (stability/FloquetMultipliers) on the Brusselator ODE, whose orbits are known to 10 digits from
// an independent integration (RK4 with 2e5 to 8e5 steps per period and the variational equations,
// converged to the digits given; docs/periodic_orbits.md), and the Floquet solver on matrices
// with known eigenvalues.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>

#include <fmt/format.h>

#include <Eigen/SVD>

#include "continuation/orbits/OrbitContinuation.hpp"
#include "continuation/orbits/OrbitCorrector.hpp"
#include "continuation/orbits/ShootingMap.hpp"
#include "runs/FloquetAnalysis.hpp"
#include "stability/FloquetMultipliers.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using keller::test::FunctionProblem;

namespace {

FunctionProblem brusselator(double a, double b) { return keller::test::brusselator_ode(a, b); }

class Last final : public TimeObserver {
 public:
  void on_step(const TimePoint& p) override { u = p.u; }
  Vector u;
};

struct Orbit {
  double period = 0.0;
  FloquetResult floquet;
  OrbitCorrection correction;
  int steps = 0;
};

// The orbit at (a, b) from a state integrated for 60 time units towards it, with the period
// guessed 2% off, on the grid of an adaptive run at relative tolerance rtol.
Orbit orbit(double a, double b, double rtol, TimeOptions::Method method,
            ShootingOptions::Linearisation mode = ShootingOptions::Linearisation::Auto) {
  FunctionProblem p = brusselator(a, b);
  TimeOptions o;
  o.t_end = 60.0;
  o.relative_tolerance = 1e-6;
  Last last;
  Vector u0(2);
  u0 << a + 0.2, b / a;
  SparseLUOptions umfpack;
  umfpack.backend = SparseLUOptions::Backend::Umfpack;
  TimeIntegrator(p, o, {}, umfpack).run(u0, 0.0, last);
  Vector u = last.u, F;
  double T = 1.02 * 7.156919921;
  o.relative_tolerance = rtol;
  o.absolute_tolerance = 1e-3 * rtol;
  o.method = method;
  const OrbitGrid grid = record_grid(p, u, T, o, ShootingOptions::tight_newton());
  ShootingOptions so;
  so.linearisation = mode;
  ShootingMap map(p, 1, so);
  (void)p.residual(u, F);
  const Vector ref = u;
  double lambda = 0.0;
  Orbit out;
  out.steps = grid.steps();
  out.correction = OrbitCorrector(map).correct(u, T, lambda, false, grid, ref, F);
  out.period = T;
  auto M = [&](const Vector& v, Vector& Mv) { return map.linearised(v, 0.0, 0.0, Mv); };
  EXPECT_TRUE(floquet_multipliers(2, M, {}, out.floquet).is_ok());
  return out;
}

}  // namespace

// The Brusselator's orbit at a = 1, b = 3 from the independent values T = 7.156919921 and nontrivial
// multiplier 2.51638e-4 (their last digits: 7e-11 and 2e-6 relative). With SDIRK4 at rtol 1e-10
// the discrete orbit's period errs by 3e-11 and its trivial multiplier by 1e-9 (measured; 1e-7 and
// 1e-8 at 1e-8 and 1e-9: the error falls about tenfold per decade of the tolerance), so the bounds
// below hold with a margin of 3 to 10.
TEST(PeriodicOrbit, BrusselatorPeriodAndMultipliersAgreeWithAnIndependentIntegration) {
  const Orbit o = orbit(1.0, 3.0, 1e-10, TimeOptions::Method::Sdirk4);
  ASSERT_TRUE(o.correction.status.is_ok()) << o.correction.status.describe();
  EXPECT_LE(o.correction.iterations, 5);  // Newton on the frozen grid: quadratic from 2% off
  EXPECT_NEAR(o.period / 7.156919921, 1.0, 2e-10);
  ASSERT_EQ(o.floquet.multipliers.size(), 2u);
  ASSERT_EQ(o.floquet.trivial, 0);
  EXPECT_NEAR(o.floquet.multipliers[0].real(), 1.0, 1e-8);
  EXPECT_NEAR(o.floquet.multipliers[1].real(), 2.51638e-4, 1e-9);
  EXPECT_EQ(o.floquet.multipliers[1].imag(), 0.0);
  EXPECT_EQ(o.floquet.stability(), "stable");
}

// The trivial multiplier's error is the integrator's, and falls as the tolerance tightens: from rtol
// 1e-6 to 1e-8, BDF2's from 5.4e-4 to 2.3e-5 (602 to 2753 steps; O(tol^(2/3)), a factor 22) and
// SDIRK4's from 8.4e-6 to 9.6e-8 (132 to 383 steps; a factor 88), measured.
TEST(PeriodicOrbit, TheTrivialMultiplierConvergesToOneWithTheTolerance) {
  for (auto method : {TimeOptions::Method::Bdf2, TimeOptions::Method::Sdirk4}) {
    const bool bdf = method == TimeOptions::Method::Bdf2;
    double before = 0.0;
    for (double rtol : {1e-6, 1e-8}) {
      const Orbit o = orbit(1.0, 3.0, rtol, method);
      ASSERT_TRUE(o.correction.status.is_ok()) << o.correction.status.describe();
      const double e = std::abs(o.floquet.multipliers[static_cast<size_t>(o.floquet.trivial)] - 1.0);
      if (before > 0.0) {
        EXPECT_LT(e, (bdf ? 0.1 : 0.02) * before) << rtol;
      }
      before = e;
    }
  }
}

namespace {

// A fixed random basis I + spread R (R uniform in [-1, 1], from the seed).
Eigen::MatrixXd random_basis(int n, unsigned seed, double spread) {
  std::srand(seed);
  return Eigen::MatrixXd::Identity(n, n) + spread * Eigen::MatrixXd::Random(n, n);
}

// The fixed random basis of with_eigenvalues.
Eigen::MatrixXd eigenvectors(int n) { return random_basis(n, 3, 0.3); }

// Puts the values on D's diagonal from index 0 (a complex one, with its conjugate next to it in
// `values`, as a real 2 x 2 block [a b; -b a]); returns the next free index.
int put_eigenvalues(Eigen::MatrixXd& D, const std::vector<std::complex<double>>& values) {
  int i = 0;
  for (size_t k = 0; k < values.size(); ++k) {
    const auto v = values[k];
    if (v.imag() == 0.0) {
      D(i, i) = v.real();
      ++i;
    } else {
      D(i, i) = D(i + 1, i + 1) = v.real();
      D(i, i + 1) = v.imag();
      D(i + 1, i) = -v.imag();
      i += 2;
      ++k;  // the conjugate
    }
  }
  return i;
}

// A real n x n matrix with the given eigenvalues (complex ones with their conjugates next to them),
// in a fixed random basis.
Eigen::MatrixXd with_eigenvalues(const std::vector<std::complex<double>>& values, int n) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  for (int i = put_eigenvalues(D, values); i < n; ++i) D(i, i) = 1e-3 * std::pow(0.9, i);  // the strongly damped rest
  const Eigen::MatrixXd S = eigenvectors(n);
  return S * D * S.inverse();
}

// M as the monodromy operator floquet_multipliers takes (M must outlive it).
std::function<Status(const Vector&, Vector&)> applying(const Eigen::MatrixXd& M) {
  return [&M](const Vector& v, Vector& y) {
    y = M * v;
    return Status{};
  };
}

// The condition number of the eigenvalue of S D S^-1 at D's index i (of a pair, the first index:
// its 2 x 2 block [a b; -b a]'s eigenvalue a + ib, right vector (1, i), left (1, -i)): |x| |y| /
// |y^T x| for its right and left eigenvectors. A Ritz value with residual r is an eigenvalue of
// M + E with |E| = r, so to first order it lies within that times r of this eigenvalue.
double eigenvalue_condition(const Eigen::MatrixXd& S, int i, bool pair) {
  const long n = S.rows();
  Eigen::VectorXcd v = Eigen::VectorXcd::Zero(n), w = Eigen::VectorXcd::Zero(n);
  v[i] = w[i] = 1.0;
  if (pair) {
    v[i + 1] = {0.0, 1.0};
    w[i + 1] = {0.0, -1.0};
  }
  const Eigen::VectorXcd x = S.cast<std::complex<double>>() * v;
  const Eigen::RowVectorXcd y = w.transpose() * Eigen::MatrixXd(S.inverse()).cast<std::complex<double>>();
  return x.norm() * y.norm() / std::abs((y * x).value());
}

}  // namespace

// Both paths (M formed and eigenvalues dense for n <= 20 here; Arnoldi on the operator above) find a
// known set: a trivial 1, a pair outside the unit circle (a Neimark-Sacker side), -1.5 (a period
// doubling side) and damped ones; the pair comes with its conjugate, by |mu| descending.
TEST(FloquetMultipliers, KnownEigenvaluesByBothPaths) {
  const std::complex<double> pair(0.6, 1.0);
  const std::vector<std::complex<double>> values{1.0, pair, std::conj(pair), -1.5, 0.5};
  for (int n : {12, 80}) {
    const Eigen::MatrixXd M = with_eigenvalues(values, n);
    const auto op = applying(M);
    FloquetOptions o;
    o.count = 5;
    FloquetResult r;
    ASSERT_TRUE(floquet_multipliers(n, op, o, r).is_ok());
    EXPECT_EQ(r.dense, n <= 20);
    ASSERT_GE(r.multipliers.size(), 5u);
    EXPECT_NEAR(std::abs(r.multipliers[0] - (-1.5)), 0.0, 1e-9) << n;
    EXPECT_NEAR(std::abs(r.multipliers[1] - pair), 0.0, 1e-9) << n;  // |pair| = 1.17
    EXPECT_NEAR(std::abs(r.multipliers[2] - std::conj(pair)), 0.0, 1e-9) << n;
    EXPECT_NEAR(std::abs(r.multipliers[3] - 1.0), 0.0, 1e-9) << n;
    EXPECT_NEAR(std::abs(r.multipliers[4] - 0.5), 0.0, 1e-9) << n;
    EXPECT_EQ(r.trivial, 3);
    EXPECT_EQ(r.unstable, 3);
    EXPECT_EQ(r.stability(), "unstable (3)");
    if (n > 20) {
      EXPECT_LT(r.applications, n);
    }
  }
}

// A dissipative flow's monodromy matrix: three multipliers that matter (1, 0.8 and -0.3) and the
// rest at 1e-13 .. 1e-11, the size of a linearised pass's own error. Eight are asked for. A test
// relative to each |mu| (ARPACK's) cannot be met by the tiny ones, which restart it up to its limit (minutes
// on the collapsible channel); measured
// against max(1, |mu_1|) the run ends within two bases, with the three to 1e-10 and the tiny ones
// reported below 1e-9.
TEST(FloquetMultipliers, TinyMultipliersDoNotStallTheArnoldiIteration) {
  const int n = 120;
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  D(0, 0) = 1.0;
  D(1, 1) = 0.8;
  D(2, 2) = -0.3;
  for (int i = 3; i < n; ++i) D(i, i) = 1e-13 * (1.0 + 99.0 * (i - 3) / (n - 4.0));
  const Eigen::MatrixXd S = random_basis(n, 5, 0.2);
  const Eigen::MatrixXd M = S * D * S.inverse();
  const auto op = applying(M);
  FloquetOptions o;
  o.count = 8;
  FloquetResult r;
  ASSERT_TRUE(floquet_multipliers(n, op, o, r).is_ok());
  ASSERT_GE(r.multipliers.size(), 8u);
  EXPECT_NEAR(std::abs(r.multipliers[0] - 1.0), 0.0, 1e-10);
  EXPECT_NEAR(std::abs(r.multipliers[1] - 0.8), 0.0, 1e-10);
  EXPECT_NEAR(std::abs(r.multipliers[2] + 0.3), 0.0, 1e-10);
  for (size_t k = 3; k < r.multipliers.size(); ++k) EXPECT_LT(std::abs(r.multipliers[k]), 1e-9) << k;
  EXPECT_LE(r.applications, 60);
  EXPECT_EQ(r.trivial, 0);
  EXPECT_EQ(r.stability(), "stable");
}

// What a multiplier must resolve, as a function: the tolerance within half of the unit circle's
// distance (at 1, on the circle, at 0.9999 and at 0.6), 1% of the distance from the circle beyond,
// inside or outside.
TEST(FloquetMultipliers, AMultiplierFarFromTheCircleIsAllowedAShareOfItsDistance) {
  FloquetOptions o;
  o.tolerance = 1e-6;
  EXPECT_EQ(o.allowed_residual(0.2), 1e-6);  // no share: the tolerance alone
  o.circle_share = 1e-2;
  EXPECT_EQ(o.allowed_residual(1.0), 1e-6);
  EXPECT_EQ(o.allowed_residual(0.9999), 1e-6);
  EXPECT_EQ(o.allowed_residual(0.6), 1e-6);
  EXPECT_EQ(o.allowed_residual(std::complex<double>(0.6, 0.8)), 1e-6);  // |mu| = 1
  EXPECT_DOUBLE_EQ(o.allowed_residual(0.2), 8e-3);
  EXPECT_DOUBLE_EQ(o.allowed_residual(std::complex<double>(0.0, -0.5)), 5e-3);
  EXPECT_DOUBLE_EQ(o.allowed_residual(-1.5), 5e-3);
  EXPECT_EQ(o.allowed_residual(-1.4), 1e-6);
  o.tolerance = -1.0;  // never met, with or without the share
  EXPECT_EQ(o.allowed_residual(1.0), 0.0);
}

// A spectrum like the collapsible channel's orbits' (docs/periodic_orbits.md): the trivial 1, 0.97,
// then multipliers of magnitude 0.17 to 0.27 in a cluster that goes on below them. Six wanted: to
// 1e-6 alone Arnoldi must separate the cluster; with 1% of the distance from the circle for those
// far from it, it stops sooner (measured: 13 applications against 24), and each multiplier is still
// within twice its allowed residual times its condition number of the truth (first-order
// perturbation, doubled for the second order; the condition numbers are 1.45 to 1.71), near the
// circle to 1e-6 (measured: 1 and 0.97 to 4e-10 and 2e-10, the cluster to 2.4e-4 of its 8e-3).
TEST(FloquetMultipliers, ACircleShareStopsSoonerWithEachMultiplierWithinItsShare) {
  const int n = 120;
  // each wanted multiplier, and its index in D (of a pair, the first)
  const std::vector<std::pair<std::complex<double>, int>> wanted{
      {1.0, 0}, {0.97, 1}, {0.27, 2}, {{-0.17, 0.03}, 3}, {{-0.17, -0.03}, 3}, {{-0.1, 0.14}, 5}, {{-0.1, -0.14}, 5}};
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  std::vector<std::complex<double>> values;
  for (const auto& w : wanted) values.push_back(w.first);
  for (int i = put_eigenvalues(D, values); i < n; ++i)
    D(i, i) = (i % 2 ? 0.15 : -0.15) * std::pow(0.95, i - 7);  // the cluster below
  const Eigen::MatrixXd S = random_basis(n, 7, 0.1);
  const Eigen::MatrixXd M = S * D * S.inverse();
  const auto op = applying(M);
  FloquetOptions o;
  o.count = 6;
  o.tolerance = 1e-6;
  FloquetResult alone, shared;
  ASSERT_TRUE(floquet_multipliers(n, op, o, alone).is_ok());
  o.circle_share = 1e-2;
  ASSERT_TRUE(floquet_multipliers(n, op, o, shared).is_ok());
  ASSERT_EQ(alone.multipliers.size(), wanted.size());
  ASSERT_EQ(shared.multipliers.size(), wanted.size());
  for (const auto& [want, index] : wanted) {
    const double condition = eigenvalue_condition(S, index, want.imag() != 0.0);
    auto nearest = [&](const FloquetResult& r) {
      double d = INFINITY;
      for (const auto& f : r.multipliers) d = std::min(d, std::abs(f - want));
      return d;
    };
    EXPECT_LT(nearest(alone), 2.0 * condition * o.tolerance) << want;
    EXPECT_LT(nearest(shared), 2.0 * condition * o.allowed_residual(want)) << want;
  }
  EXPECT_LT(shared.applications, alone.applications);
}

// A branch's next orbit: started from the last orbit's Ritz vectors (FloquetOptions::start, as
// runs/FloquetAnalysis does), Arnoldi finds the perturbed matrix's multipliers as a cold start does,
// to 1e-9, in fewer applications of M.
TEST(FloquetMultipliers, AWarmStartFromTheLastRitzVectorsFindsTheSameMultipliersSooner) {
  const std::complex<double> pair(0.6, 1.0);
  const Eigen::MatrixXd M0 = with_eigenvalues({1.0, pair, std::conj(pair), -0.9, 0.5}, 80);
  std::srand(11);
  const Eigen::MatrixXd M1 = M0 + 1e-3 * Eigen::MatrixXd::Random(80, 80);
  FloquetOptions o;
  o.count = 5;
  FloquetResult first, cold, warm;
  ASSERT_TRUE(floquet_multipliers(80, applying(M0), o, first).is_ok());
  ASSERT_EQ(first.ritz.size(), first.multipliers.size());
  ASSERT_TRUE(floquet_multipliers(80, applying(M1), o, cold).is_ok());
  o.start = first.ritz;
  ASSERT_TRUE(floquet_multipliers(80, applying(M1), o, warm).is_ok());
  ASSERT_EQ(warm.multipliers.size(), cold.multipliers.size());
  for (size_t k = 0; k < cold.multipliers.size(); ++k)
    EXPECT_NEAR(std::abs(warm.multipliers[k] - cold.multipliers[k]), 0.0, 1e-9) << k;
  EXPECT_LT(warm.applications, cold.applications);
}

// The classification alone: the trivial multiplier is the one nearest 1, whatever its place, and
// only the others count towards instability (a multiplier at 1 + 1e-9 is the trivial one, not an
// unstable one).
TEST(FloquetMultipliers, TheTrivialOneIsNearestOneAndNotCounted) {
  FloquetResult r;
  r.multipliers = {{-2.0, 0.0}, {1.0 + 1e-9, 0.0}, {0.99, 0.0}, {0.2, 0.1}, {0.2, -0.1}};
  classify_multipliers(r);
  EXPECT_EQ(r.trivial, 1);
  EXPECT_EQ(r.unstable, 1);
  r.multipliers = {{1.2, 0.0}, {0.9999999, 0.0}};
  classify_multipliers(r);
  EXPECT_EQ(r.trivial, 1);
  EXPECT_EQ(r.unstable, 1);
  r.multipliers = {{0.5, 0.0}};
  classify_multipliers(r);
  EXPECT_EQ(r.stability(), "stable");
}

// The matrix-free linearisation that large problems take (GMRES on differences of each solve's
// residual, preconditioned by a few factorisations) gives the orbit of the factorised one: the same
// Newton iterations and period to 1e-12 (the orbit's equations are the same; only the Newton
// matrix's products differ), the multipliers to the passes' 1e-7 (ShootingMap's test; measured 7e-8).
TEST(PeriodicOrbit, ThePreconditionedLinearisationGivesTheSameOrbit) {
  using L = ShootingOptions::Linearisation;
  const Orbit f = orbit(1.0, 3.0, 1e-8, TimeOptions::Method::Sdirk4, L::Factorised);
  const Orbit p = orbit(1.0, 3.0, 1e-8, TimeOptions::Method::Sdirk4, L::Preconditioned);
  ASSERT_TRUE(p.correction.status.is_ok()) << p.correction.status.describe();
  EXPECT_EQ(p.correction.iterations, f.correction.iterations);
  EXPECT_NEAR(p.period, f.period, 1e-12 * f.period);
  ASSERT_EQ(p.floquet.multipliers.size(), f.floquet.multipliers.size());
  for (size_t i = 0; i < f.floquet.multipliers.size(); ++i)
    EXPECT_NEAR(std::abs(p.floquet.multipliers[i] - f.floquet.multipliers[i]), 0.0, 2e-7) << i;
}

// The corrector's policies as functions. The passes of a Newton step take 1e-4 of its forcing
// term, never below the tightest pass. Newton stops where the residual is within the
// tolerance and so is the error: the last update, or the next one estimated from it by the
// residuals' contraction where that is small enough to trust.
TEST(OrbitCorrector, PassToleranceAndStopAsFunctions) {
  EXPECT_DOUBLE_EQ(OrbitCorrector::pass_tolerance(1e-2), 1e-6);
  EXPECT_DOUBLE_EQ(OrbitCorrector::pass_tolerance(1e-6), 1e-10);
  EXPECT_DOUBLE_EQ(OrbitCorrector::pass_tolerance(1e-9), ShootingMap::kTightPass);
  const double tol = 1e-9;
  EXPECT_FALSE(OrbitCorrector::converged(2e-9, 1e-12, 1e-3, tol));  // residual too large
  EXPECT_TRUE(OrbitCorrector::converged(1e-9, 1e-9, 0.9, tol));     // the last update small: the old test
  EXPECT_TRUE(OrbitCorrector::converged(5e-11, 1e-7, 4e-3, tol));   // next update ~4e-10
  EXPECT_FALSE(OrbitCorrector::converged(5e-11, 1e-6, 4e-3, tol));  // next update ~4e-9
  EXPECT_FALSE(OrbitCorrector::converged(5e-11, 5e-9, 0.15, tol));  // contraction too slow to trust
  EXPECT_TRUE(OrbitCorrector::converged(5e-11, 5e-9, 0.1, tol));
  EXPECT_FALSE(OrbitCorrector::converged(5e-11, 5e-9, std::nan(""), tol));
}

// A branch records a new grid from an orbit where the orbit's integration on its grid fails the
// integrator's error test somewhere, or was not estimated (BDF2), and keeps the grid otherwise.
TEST(OrbitContinuation, ANewGridWhereTheOldOneFailsTheErrorTest) {
  EXPECT_FALSE(OrbitContinuation::records_grid(0.5));
  EXPECT_FALSE(OrbitContinuation::records_grid(1.0));
  EXPECT_TRUE(OrbitContinuation::records_grid(1.01));
  EXPECT_TRUE(OrbitContinuation::records_grid(std::numeric_limits<double>::infinity()));
  EXPECT_TRUE(OrbitContinuation::records_grid(std::nan("")));
}

// The multipliers' accuracy follows their passes' (OrbitContinuation::multiplier_accuracy): exact
// passes (every solve factorised, B constant) keep Arnoldi's 1e-10 on passes at 1e-12; GMRES passes
// take 1e-6, or for a multiplier at least 1/2 from the unit circle 1% of its distance from it, on
// passes at 1e-9, a thousandth of the tolerance (a pass errs by its solves' tolerances added up
// over the period: 62 of them in ShootingMap's test). Which passes a map makes is its own
// (ShootingMap::exact_passes), and the analysis honours the accuracy it is given: on a matrix with
// known multipliers, those near the circle to 1e-9 and 1e-6, the one far from it within its allowed
// residual times its condition number, doubled, and in fewer applications than at 1e-10.
TEST(OrbitContinuation, TheMultipliersAccuracyFollowsThePassesAsFunctions) {
  EXPECT_EQ(OrbitContinuation::multiplier_accuracy(true).tolerance, 0.0);  // the analysis's own
  EXPECT_EQ(OrbitContinuation::multiplier_accuracy(true).circle_share, 0.0);
  EXPECT_EQ(OrbitContinuation::multiplier_pass_tolerance(true), ShootingMap::kTightPass);
  EXPECT_DOUBLE_EQ(OrbitContinuation::multiplier_accuracy(false).tolerance, 1e-6);
  EXPECT_DOUBLE_EQ(OrbitContinuation::multiplier_accuracy(false).circle_share, 1e-2);
  EXPECT_DOUBLE_EQ(OrbitContinuation::multiplier_pass_tolerance(false), 1e-9);

  using L = ShootingOptions::Linearisation;
  for (L mode : {L::Factorised, L::Preconditioned}) {
    FunctionProblem p = brusselator(1.0, 3.0);
    TimeOptions o;
    o.relative_tolerance = 1e-6;
    Vector u0(2);
    u0 << 1.5, 2.0;
    const OrbitGrid grid = record_grid(p, u0, 3.0, o, ShootingOptions::tight_newton());
    ShootingOptions so;
    so.linearisation = mode;
    ShootingMap map(p, 1, so);
    ASSERT_TRUE(map.integrate(u0, 3.0, grid).is_ok());
    EXPECT_EQ(map.exact_passes(), mode == L::Factorised);
  }

  const std::complex<double> pair(0.3, 0.5);
  const std::vector<std::complex<double>> values{1.0, 0.8, pair, std::conj(pair), -0.4};
  const Eigen::MatrixXd M = with_eigenvalues(values, 80);
  const auto op = applying(M);
  const std::vector<int> index{0, 1, 2, 2, 4};  // each value's in with_eigenvalues' D
  long applications[2] = {0, 0};
  for (int loose = 0; loose < 2; ++loose) {
    FloquetAnalysis analysis = FloquetAnalysis::for_branch(5);
    std::vector<std::complex<double>> found;
    int trivial = -1;
    const MultiplierAccuracy accuracy = OrbitContinuation::multiplier_accuracy(!loose);
    ASSERT_TRUE(analysis.compute(80, op, found, trivial, nullptr, accuracy).is_ok());
    applications[loose] = analysis.last().applications;
    ASSERT_EQ(found.size(), 5u);
    FloquetOptions allowed;
    if (loose) allowed.tolerance = accuracy.tolerance;
    allowed.circle_share = accuracy.circle_share;
    for (size_t k = 0; k < values.size(); ++k) {
      const auto want = values[k];
      double nearest = INFINITY;
      for (const auto& f : found) nearest = std::min(nearest, std::abs(f - want));
      // near the circle as before the share (measured: loose 4.4e-8, tight 7e-12); -0.4, 0.6 from it,
      // within twice its allowed residual times its condition number (4.8; first order, doubled)
      const double far =
          2.0 * eigenvalue_condition(eigenvectors(80), index[k], want.imag() != 0.0) * allowed.allowed_residual(want);
      EXPECT_LT(nearest, std::abs(std::abs(want) - 1.0) < FloquetOptions::kFarFromCircle ? (loose ? 1e-6 : 1e-9) : far)
          << want << (loose ? " loose" : " tight");
    }
    EXPECT_EQ(trivial, 0);
  }
  EXPECT_LT(applications[1], applications[0]);
}
