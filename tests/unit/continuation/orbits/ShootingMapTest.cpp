// The shooting map of periodic orbits (continuation/orbits/ShootingMap): the integrator on a given
// grid reproduces the adaptive run the grid came from, and the linearised passes (the monodromy
// matrix and the derivatives in the period and the parameter) agree with central differences of
// the map itself, for BDF2 and SDIRK4, with B constant and with B depending on u (the B'[v] R term),
// with every solve's matrix factorised and by GMRES preconditioned by a few of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <vector>

#include "continuation/orbits/ShootingMap.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using keller::test::FunctionProblem;

namespace {

// The Brusselator ODE x' = a - (b + 1) x + x^2 y, y' = b x - x^2 y as B du/dt = -F, B = I.
FunctionProblem brusselator(double a, double b) { return keller::test::brusselator_ode(a, b); }

// The same equations with a state-dependent mass matrix B(u) = diag(1 + x^2 / 2, 1 + y^2 / 4)
// (a moving mesh's kind of time term).
class CurvedMass final : public Problem {
 public:
  explicit CurvedMass(FunctionProblem inner) : inner_(std::move(inner)) {}
  std::string name() const override { return "curved-mass"; }
  int size() const override { return 2; }
  ParameterSet& parameters() override { return inner_.parameters(); }
  const ParameterSet& parameters() const override { return inner_.parameters(); }
  const SparseMatrix& jacobian_pattern() const override { return inner_.jacobian_pattern(); }
  Status residual(const Vector& u, Vector& F) override { return inner_.residual(u, F); }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override { return inner_.jacobian(u, F, J); }
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override {
    return inner_.parameter_derivative(p, u, dF);
  }
  Status mass_matrix(const Vector& u, SparseMatrix& B) override {
    B = inner_.jacobian_pattern();
    B.coeffRef(0, 0) = 1.0 + 0.5 * u[0] * u[0];
    B.coeffRef(1, 1) = 1.0 + 0.25 * u[1] * u[1];
    return {};
  }
  Vector initial_guess() override { return Vector::Zero(2); }

 private:
  FunctionProblem inner_;
};

class States final : public TimeObserver {
 public:
  void on_step(const TimePoint& p) override {
    if (p.step > 0) times.push_back(p.t);
    states.push_back(p.u);
  }
  std::vector<double> times;
  std::vector<Vector> states;
};

Vector start() {
  Vector u(2);
  u << 1.5, 2.0;
  return u;
}

}  // namespace

TEST(ShootingMap, TheGridReproducesTheAdaptiveRunItCameFrom) {
  FunctionProblem p = brusselator(1.0, 3.0);
  TimeOptions o;
  o.t_end = 5.0;
  o.relative_tolerance = 1e-6;
  o.absolute_tolerance = 1e-10;
  States adaptive, fixed;
  ASSERT_EQ(TimeIntegrator(p, o, ShootingOptions::tight_newton()).run(start(), 0.0, adaptive).code, TimeStop::End);
  ASSERT_GT(adaptive.times.size(), 20u);
  const TimeResult r =
      TimeIntegrator(p, o, ShootingOptions::tight_newton()).run_on_grid(start(), 0.0, adaptive.times, fixed);
  ASSERT_EQ(r.code, TimeStop::End) << r.reason;
  ASSERT_EQ(fixed.states.size(), adaptive.states.size());
  // the same steps from the same states: equal to the steps' Newton tolerance (1e-13)
  for (size_t k = 0; k < fixed.states.size(); ++k)
    EXPECT_LT((fixed.states[k] - adaptive.states[k]).lpNorm<Eigen::Infinity>(), 1e-11) << "state " << k;
}

TEST(ShootingMap, AGridStepThatFailsEndsTheRunWithAReason) {
  FunctionProblem p = brusselator(1.0, 3.0);
  NewtonOptions newton = ShootingOptions::tight_newton();
  newton.max_iterations = 1;  // no step converges in one iteration from the predictor
  States s;
  const TimeResult r = TimeIntegrator(p, TimeOptions{}, newton).run_on_grid(start(), 0.0, {0.5, 1.0, 1.5}, s);
  EXPECT_EQ(r.code, TimeStop::GridStepFailed);
  EXPECT_NE(r.reason.find("step 1 of the grid"), std::string::npos) << r.reason;
  EXPECT_THROW(TimeIntegrator(p, TimeOptions{}).run_on_grid(start(), 0.0, {0.5, 0.4}, s), std::invalid_argument);
}

namespace {

// |linearised - central difference| / |linearised| for the direction (v, dT, dlambda).
double linearisation_error(Problem& p, const Vector& v, double dT, double dl, TimeOptions::Method method,
                           ShootingOptions::Linearisation mode) {
  const double T = 3.0, eps = 1e-3;
  TimeOptions o;
  o.method = method;
  o.relative_tolerance = 1e-5;
  const OrbitGrid grid = record_grid(p, start(), T, o, ShootingOptions::tight_newton());
  EXPECT_GT(grid.steps(), method == TimeOptions::Method::Bdf2 ? 20 : 5);
  ShootingOptions so;
  so.linearisation = mode;
  ShootingMap map(p, 1, so);
  const double b = p.parameters().value(1);
  EXPECT_TRUE(map.integrate(start(), T, grid).is_ok());
  Vector exact;
  EXPECT_TRUE(map.linearised(v, dT, dl, exact).is_ok());
  auto phi = [&](double s) {
    p.parameters().set(1, b + s * dl);
    EXPECT_TRUE(map.integrate(start() + s * v, T + s * dT, grid).is_ok());
    p.parameters().set(1, b);
    return map.end();
  };
  // central differences at eps and 2 eps, extrapolated (Richardson): the eps^2 term cancels
  const Vector d1 = (phi(eps) - phi(-eps)) / (2.0 * eps), d2 = (phi(2 * eps) - phi(-2 * eps)) / (4.0 * eps);
  const Vector fd = (4.0 * d1 - d2) / 3.0;
  return (fd - exact).norm() / exact.norm();
}

// The grid of an adaptive run over T from start() at rtol 1e-6, and the options of a map whose
// solves are GMRES on a few anchors' factorisations.
OrbitGrid grid_at_rtol_1e6(Problem& p, double T, TimeOptions::Method method) {
  TimeOptions o;
  o.method = method;
  o.relative_tolerance = 1e-6;
  return record_grid(p, start(), T, o, ShootingOptions::tight_newton());
}

ShootingOptions preconditioned() {
  ShootingOptions so;
  so.linearisation = ShootingOptions::Linearisation::Preconditioned;
  return so;
}

}  // namespace

// The reference: central differences of the map at 1e-3 and 2e-3, extrapolated. Their error is
// O(eps^4) times the map's fifth derivative (1e-12 here) plus the steps' Newton tolerance over eps
// (1e-13 / 1e-3), so about 1e-10 relative, below what each pass is asked for.
TEST(ShootingMap, LinearisedPassesAgreeWithDifferencesOfTheMap) {
  Vector v(2);
  v << 0.3, -0.7;
  using L = ShootingOptions::Linearisation;
  for (auto mode : {L::Factorised, L::Preconditioned})
    for (auto method : {TimeOptions::Method::Bdf2, TimeOptions::Method::Sdirk4})
      for (int constant = 1; constant >= 0; --constant) {
        FunctionProblem f = brusselator(1.0, 3.0);
        CurvedMass curved(brusselator(1.0, 3.0));
        Problem& p = constant ? static_cast<Problem&>(f) : static_cast<Problem&>(curved);
        SCOPED_TRACE(p.name() + (method == TimeOptions::Method::Bdf2 ? " BDF2" : " SDIRK4") +
                     (mode == L::Factorised ? " factorised" : " preconditioned"));
        // exact passes (factorised, B constant): measured 2e-10 (BDF2) and 1.5e-9 (SDIRK4), the
        // reference's own error; products by differences (preconditioned, and wherever B varies:
        // the B'[dU] R term) leave their truncation and rounding in each solve, which the period's
        // 500 solves accumulate against a strongly contracted |M v|: measured 1.4e-8 at worst
        // with the step of 1e-5, and 1.2e-7 with 1e-6, which this tolerance refuses
        const double tol = mode == L::Factorised && constant ? 1e-8 : 5e-8;
        EXPECT_LT(linearisation_error(p, v, 0.0, 0.0, method, mode), tol) << "M v";
        EXPECT_LT(linearisation_error(p, Vector::Zero(2), 1.0, 0.0, method, mode), tol) << "dPhi/dT";
        EXPECT_LT(linearisation_error(p, Vector::Zero(2), 0.0, 1.0, method, mode), tol) << "dPhi/db";
        EXPECT_LT(linearisation_error(p, v, 0.4, -0.2, method, mode), tol) << "all three";
      }
}

// Auto's choice of linearisation as a function: Factorised only for a constant B, at most
// kFactorisedSize unknowns and factorisations that fit in the budget together; anything asked
// explicitly is kept.
TEST(ShootingMap, AutoLinearisationFactorisesOnlyConstantMassesThatFit) {
  using L = ShootingOptions::Linearisation;
  const int small = ShootingOptions::kFactorisedSize, large = ShootingOptions::kFactorisedSize + 1;
  EXPECT_EQ(ShootingOptions::linearisation_for(L::Auto, small, false, 1e6, 1000, 2e9), L::Factorised);
  EXPECT_EQ(ShootingOptions::linearisation_for(L::Auto, small, false, 1e6, 2000, 2e9), L::Factorised);  // = budget
  EXPECT_EQ(ShootingOptions::linearisation_for(L::Auto, small, false, 1e6, 2001, 2e9), L::Preconditioned);
  EXPECT_EQ(ShootingOptions::linearisation_for(L::Auto, small, false, -1.0, 100000, 2e9), L::Factorised);
  EXPECT_EQ(ShootingOptions::linearisation_for(L::Auto, small, true, 1e3, 10, 2e9), L::Preconditioned);
  EXPECT_EQ(ShootingOptions::linearisation_for(L::Auto, large, false, 1e3, 10, 2e9), L::Preconditioned);
  EXPECT_EQ(ShootingOptions::linearisation_for(L::Factorised, large, true, 1e9, 1000, 1.0), L::Factorised);
  EXPECT_EQ(ShootingOptions::linearisation_for(L::Preconditioned, 10, false, 1.0, 1, 2e9), L::Preconditioned);
}

// A pass asked for a looser tolerance (a Newton step's, OrbitCorrector::pass_tolerance) takes fewer
// inner GMRES iterations, and its result differs from the tightest pass's by no more than the
// tolerance times the period's solves (each solve errs by at most the tolerance of its right-hand
// side, and the errors add up along the period: about 100 solves here, so 1e3 tolerances is a
// bound the test can fail; measured 62 at 1e-6); a tolerance outside [kTightPass, 1e-2] is clamped.
// Every solve but the first starts from the last solve's change of rate (dU = shift + dR_last /
// (dR/dU)) and GMRES solves for the rest to the same residual; a guess left out of the sum would
// err by the whole guess. (On the channel of docs/periodic_orbits.md the guess leaves 1e-4 to 1e-6
// of the right-hand side and the passes took 7% fewer products and 16% less time; here, where the
// anchors' factorisations are nearly the solves' own, it costs more than it saves: products a
// solve at 1e-6, 2.70 against 1.96 with BDF2, 2.20 against 1.90 with SDIRK4.)
TEST(ShootingMap, ALooserPassCostsFewerInnerIterationsAndErrsWithinItsTolerance) {
  for (auto method : {TimeOptions::Method::Bdf2, TimeOptions::Method::Sdirk4}) {
    SCOPED_TRACE(method == TimeOptions::Method::Bdf2 ? "BDF2" : "SDIRK4");
    CurvedMass p(brusselator(1.0, 3.0));
    const double T = 3.0;
    const OrbitGrid grid = grid_at_rtol_1e6(p, T, method);
    ShootingMap map(p, 1, preconditioned());
    ASSERT_TRUE(map.integrate(start(), T, grid).is_ok());
    Vector v(2);
    v << 0.3, -0.7;
    auto pass = [&](double tolerance, long& inner) {
      Vector out;
      const long before = map.counts().inner_iterations;
      EXPECT_TRUE(map.linearised(v, 0.2, 0.1, out, tolerance).is_ok());
      inner = map.counts().inner_iterations - before;
      return out;
    };
    long tight_inner = 0, loose_inner = 0, clamped_inner = 0, zero_inner = 0;
    const Vector tight = pass(ShootingMap::kTightPass, tight_inner);
    const Vector loose = pass(1e-6, loose_inner);
    EXPECT_LT(loose_inner, tight_inner);

    EXPECT_LT((loose - tight).norm(), 1e3 * 1e-6 * tight.norm());
    const Vector zero = pass(0.0, zero_inner);  // 0: the tightest
    EXPECT_EQ(zero_inner, tight_inner);
    EXPECT_EQ((zero - tight).norm(), 0.0);
    const Vector clamped = pass(0.5, clamped_inner);  // at most 1e-2
    EXPECT_LT((clamped - tight).norm(), 1e3 * 1e-2 * tight.norm());
    EXPECT_LE(clamped_inner, loose_inner);
  }
}

// The grid's error check (ShootingMap::step_error): on the run the grid came from it is that run's
// own largest estimate (each accepted step's TimePoint::error; the grid reproduces the run to 1e-11,
// so the stages' rates and the estimates agree to 1e-6 of it, measured 5e-9), at most 1; over a period
// 1.6 times longer the same fractions make every step 1.6 times longer and the O(h^4) estimate about
// 6.6 times larger: above 1. BDF2 keeps none: +inf.
TEST(ShootingMap, TheStepErrorIsTheAdaptiveRunsOwnTest) {
  FunctionProblem p = brusselator(1.0, 3.0);
  TimeOptions o;
  o.method = TimeOptions::Method::Sdirk4;
  o.relative_tolerance = 1e-6;
  o.absolute_tolerance = 1e-10;
  const double T = 3.0;
  class Errors final : public TimeObserver {
   public:
    void on_step(const TimePoint& q) override {
      if (q.step == 0) return;
      times.push_back(q.t);
      worst = std::max(worst, q.error);
    }
    std::vector<double> times;
    double worst = 0.0;
  } run;
  o.t_end = T;
  TimeIntegrator adaptive(p, o, ShootingOptions::tight_newton(), ShootingOptions::chord_lu({}));
  ASSERT_EQ(adaptive.run(start(), 0.0, run).code, TimeStop::End);
  const OrbitGrid grid = OrbitGrid::from_times(0.0, run.times, o.method);
  ShootingMap map(p, 1);
  ASSERT_TRUE(map.integrate(start(), T, grid).is_ok());
  const double own = map.step_error(o.relative_tolerance, o.absolute_tolerance);
  EXPECT_NEAR(own, run.worst, 1e-6 * run.worst);
  EXPECT_LE(own, 1.0);
  ASSERT_TRUE(map.integrate(start(), 1.6 * T, grid).is_ok());
  EXPECT_GT(map.step_error(o.relative_tolerance, o.absolute_tolerance), 2.0 * own);
  EXPECT_GT(map.step_error(o.relative_tolerance, o.absolute_tolerance), 1.0);
  // 100 times the tolerance: the same steps pass
  EXPECT_LT(map.step_error(1e2 * o.relative_tolerance, 1e2 * o.absolute_tolerance), 1.0);

  o.method = TimeOptions::Method::Bdf2;
  const OrbitGrid bdf = record_grid(p, start(), T, o, ShootingOptions::tight_newton());
  ASSERT_TRUE(map.integrate(start(), T, bdf).is_ok());
  EXPECT_EQ(map.step_error(o.relative_tolerance, o.absolute_tolerance), std::numeric_limits<double>::infinity());
}

// The forward steps' LU options as a function: the given ones without iterative refinement (the
// steps' Newton is a chord on a kept factorisation), everything else as given; the passes keep the
// given refinement.
TEST(ShootingMap, TheForwardStepsSolveWithoutRefinement) {
  SparseLUOptions lu;
  lu.refinement_steps = 3;
  lu.pivot_tolerance = 0.5;
  lu.backend = SparseLUOptions::Backend::Umfpack;
  const SparseLUOptions chord = ShootingOptions::chord_lu(lu);
  EXPECT_EQ(chord.refinement_steps, 0);
  EXPECT_EQ(chord.pivot_tolerance, 0.5);
  EXPECT_EQ(chord.backend, SparseLUOptions::Backend::Umfpack);
  EXPECT_EQ(lu.refinement_steps, 3);
}

// The period's column of the shooting Newton matrix, T dPhi/dT on a grid of fixed fractions of T,
// is the flow at the period's end T f(Phi) up to the integrator's error (for the flow itself
// d/dT phi_T(u0) = f(phi_T(u0)) exactly): the corrector's preconditioner takes the second for the
// first, without a pass (BorderedDeflation in OrbitCorrector). Their difference shrinks with the
// grid's tolerance as a global error does under local error control: steps h ~ rtol^(1/(q+1)) for
// an estimate of order q + 1, an error h^p, so from rtol 1e-4 to 1e-6 by 100^(2/3) = 21.5 for BDF2
// (p = q = 2) and by 100 for SDIRK4 (p = 4, its embedded estimate O(h^4)); the test asks half of
// each (measured 18.8 and 115) and at most 1e3 rtol (measured 140 and 0.33 rtol at 1e-6).
TEST(ShootingMap, TheEndRateIsThePeriodsColumnToTheIntegratorsError) {
  for (const auto method : {TimeOptions::Method::Bdf2, TimeOptions::Method::Sdirk4}) {
    const double rate = method == TimeOptions::Method::Bdf2 ? std::pow(100.0, 2.0 / 3.0) : 100.0;
    std::vector<double> errors;
    for (const double rtol : {1e-4, 1e-6}) {
      FunctionProblem p = brusselator(1.0, 3.0);
      const double T = 3.0;
      TimeOptions o;
      o.method = method;
      o.relative_tolerance = rtol;
      const OrbitGrid grid = record_grid(p, start(), T, o, ShootingOptions::tight_newton());
      ShootingMap map(p, 1);
      ASSERT_TRUE(map.integrate(start(), T, grid).is_ok());
      Vector column;
      ASSERT_TRUE(map.linearised(Vector::Zero(2), T, 0.0, column).is_ok());
      errors.push_back((column - T * map.end_rate()).norm() / column.norm());
    }
    std::cout << (method == TimeOptions::Method::Bdf2 ? "BDF2" : "SDIRK4") << ": |T dPhi/dT - T f(Phi)| / |T dPhi/dT| "
              << errors[0] << " at rtol 1e-4, " << errors[1] << " at 1e-6\n";
    EXPECT_LT(errors[0], 1e3 * 1e-4);
    EXPECT_LT(errors[1], 1e3 * 1e-6);
    EXPECT_GT(errors[0] / errors[1], 0.5 * rate);
  }
}

// The anchors' drift as a function: the largest change of u0 (infinity norm), the period and each
// parameter, relative to max(1, the old size); infinite where the sizes differ or a value is not a
// number. The anchors serve on up to kAnchorDrift (1e-3) and are renewed beyond it.
TEST(ShootingMap, TheAnchorsDriftAndTheirRenewalAsFunctions) {
  Vector a(3), b(3);
  a << 4.0, -2.0, 0.5;
  b << 4.0, -2.04, 0.5;
  EXPECT_NEAR(ShootingOptions::anchor_drift(a, b, {10.0, 0.5}, {10.0, 0.5}), 0.01, 1e-15);   // 0.04 / 4
  EXPECT_NEAR(ShootingOptions::anchor_drift(a, a, {10.0, 0.5}, {10.3, 0.5}), 0.03, 1e-15);   // the period
  EXPECT_NEAR(ShootingOptions::anchor_drift(a, a, {10.0, 0.5}, {10.0, 0.52}), 0.02, 1e-15);  // a small parameter: on 1
  EXPECT_NEAR(ShootingOptions::anchor_drift(0.1 * a, 0.1 * b, {}, {}), 0.004, 1e-15);        // a small state: on 1
  EXPECT_NEAR(ShootingOptions::anchor_drift(a, a, {10.0}, {10.0}), 0.0, 1e-15);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(ShootingOptions::anchor_drift(a, Vector::Zero(2), {}, {}), inf);
  EXPECT_EQ(ShootingOptions::anchor_drift(a, a, {1.0}, {1.0, 2.0}), inf);
  EXPECT_EQ(ShootingOptions::anchor_drift(a, a, {1.0}, {std::nan("")}), inf);
  EXPECT_TRUE(ShootingOptions::keeps_anchors(0.0));
  EXPECT_TRUE(ShootingOptions::keeps_anchors(ShootingOptions::kAnchorDrift));
  EXPECT_FALSE(ShootingOptions::keeps_anchors(1.01 * ShootingOptions::kAnchorDrift));
  EXPECT_FALSE(ShootingOptions::keeps_anchors(inf));
}

// The anchors' factorisations serve on across integrations of the same grid while the start and
// the parameters stay within the drift (a Newton correction's iterations), and are made again where
// either moves further or the grid changes. Kept anchors only precondition: a pass on them gives
// what a new map, factorising at the present states, gives, to the passes' own accuracy (products
// by differences: 5e-8, LinearisedPassesAgreeWithDifferencesOfTheMap; measured 2e-9), in about as
// many inner iterations (measured 526 against 521).
TEST(ShootingMap, TheAnchorsServeOnWhileTheOrbitStaysNear) {
  CurvedMass p(brusselator(1.0, 3.0));
  const double T = 3.0;
  const OrbitGrid grid = grid_at_rtol_1e6(p, T, TimeOptions::Method::Sdirk4);
  const ShootingOptions so = preconditioned();
  ShootingMap map(p, 1, so);
  Vector v(2);
  v << 0.3, -0.7;
  // the factorisations of an integration's first pass (the forward run's apart)
  auto pass_factorisations = [&](const Vector& u0, double period, const OrbitGrid& g, Vector* out = nullptr) {
    EXPECT_TRUE(map.integrate(u0, period, g).is_ok());
    const long before = map.counts().factorisations;
    Vector r;
    EXPECT_TRUE(map.linearised(v, 0.0, 0.0, r).is_ok());
    if (out) *out = r;
    return map.counts().factorisations - before;
  };
  const long anchors = pass_factorisations(start(), T, grid);
  ASSERT_GT(anchors, 3);
  Vector near = start();
  near[0] += 1e-3;  // drift 5e-4 of |u0| = 2
  Vector kept;
  const long inner_before = map.counts().inner_iterations;
  EXPECT_EQ(pass_factorisations(near, T * (1.0 + 1e-4), grid, &kept), 0);
  {
    ShootingMap fresh(p, 1, so);
    ASSERT_TRUE(fresh.integrate(near, T * (1.0 + 1e-4), grid).is_ok());
    Vector own;
    ASSERT_TRUE(fresh.linearised(v, 0.0, 0.0, own).is_ok());
    const long kept_inner = map.counts().inner_iterations - inner_before;
    std::cout << "inner iterations: kept anchors " << kept_inner << ", fresh " << fresh.counts().inner_iterations
              << "; |difference| / |pass| " << (kept - own).norm() / own.norm() << "\n";
    EXPECT_GT(fresh.counts().factorisations, anchors);  // the forward run's and the anchors'
    EXPECT_LT((kept - own).norm(), 5e-8 * own.norm());
    EXPECT_LE(kept_inner, 1.1 * static_cast<double>(fresh.counts().inner_iterations));
  }
  Vector far = start();
  far[0] += 0.1;  // drift 0.05
  EXPECT_EQ(pass_factorisations(far, T, grid), anchors);
  EXPECT_EQ(pass_factorisations(far, T, grid), 0);
  const double b = p.parameters().value(1);
  p.parameters().set(1, b * 1.02);  // a parameter 2% on
  EXPECT_EQ(pass_factorisations(far, T, grid), anchors);
  p.parameters().set(1, b);
  OrbitGrid other = grid;
  other.fractions[0] *= 0.999;  // another grid
  EXPECT_GT(pass_factorisations(far, T, other), 0);
}
