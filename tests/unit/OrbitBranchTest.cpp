// Branches of periodic orbits (continuation/orbits/OrbitContinuation) with their Floquet
// multipliers (runs/FloquetAnalysis): the adaptive-control (Lur'e) system's branch from its Hopf
// point through its period doublings, against MatCont's published values.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "continuation/orbits/OrbitContinuation.hpp"
#include "runs/FloquetAnalysis.hpp"
#include "support/TestProblems.hpp"

using namespace keller;
using keller::test::FunctionProblem;
using keller::test::RecordingObserver;

namespace {

// x' = y, y' = z, z' = -alpha z - y - x + x^2 (MatCont's adaptx), B du/dt = -F.
FunctionProblem adaptive_control(double alpha) {
  return FunctionProblem(
      "adaptive-control", 3, {{"alpha", alpha}},
      [](const Vector& u, const Vector& p) {
        Vector F(3);
        F << -u[1], -u[2], p[0] * u[2] + u[1] + u[0] - u[0] * u[0];
        return F;
      },
      [](const Vector& u, const Vector& p) {
        Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3, 3);
        J(0, 1) = -1.0;
        J(1, 2) = -1.0;
        J(2, 0) = 1.0 - 2.0 * u[0];
        J(2, 1) = 1.0;
        J(2, 2) = p[0];
        return J;
      },
      [](int, const Vector& u, const Vector&) {
        Vector d = Vector::Zero(3);
        d[2] = u[2];
        return d;
      });
}

OrbitContinuationOptions options() {
  OrbitContinuationOptions o;
  o.time.method = TimeOptions::Method::Sdirk4;
  o.time.relative_tolerance = 1e-9;
  o.time.absolute_tolerance = 1e-12;
  o.step = 0.05;
  o.max_step = 0.2;
  o.max_points = 200;
  return o;
}

// The adaptive control problem's first two orbits, at alpha = 0.95 and 0.93, from the Hopf normal
// form's orbit at 0.95: |z| = sqrt(-g' (alpha - 1) / Re c1) = 0.118 with q = (1, i, -1), g' = -1/4,
// Re c1 = -0.9 (PublishedNormalForms)
// then the branch from them
OrbitContinuationResult branch_from_two_orbits(FunctionProblem& p, OrbitContinuation& c, RecordingObserver& rec) {
  Vector u0(3), flow(3);
  u0 << 0.236, 0.0, -0.236;
  flow << 0.0, -1.0, 0.0;
  OrbitPoint a, b;
  EXPECT_TRUE(c.converge(u0, 2.0 * std::numbers::pi, flow, a).is_ok());
  p.parameters().set(0, 0.93);
  EXPECT_TRUE(c.converge(a.u0, a.period, a.flow, b).is_ok());
  return c.run(a, b, rec);
}

}  // namespace

// The branch from the Hopf point at alpha = 1 down to alpha = -0.7. MatCont's manual prints the
// period doubling at alpha = 6.303020e-1 with period 6.364071; an independent RK4 shooting code
// gave 0.6303020062 and 6.3640713394 (docs/periodic_orbits.md). The third multiplier there is
// -exp(-alpha T) (Liouville: tr J = -alpha), and the map (alpha, t, x, y, z) -> (-alpha, -t, 1 - x,
// y, -z) takes the branch into itself, so a second period doubling lies at -alpha_PD. At alpha = 0
// MatCont reports a Neimark-Sacker point; there the nontrivial multipliers are real, -16.8 and
// -0.06 (a neutral saddle, not a bifurcation), and keller reports none.
TEST(OrbitBranch, AdaptiveControlPeriodDoublingsAgainstMatCont) {
  FunctionProblem p = adaptive_control(0.95);
  FloquetAnalysis floquet;
  OrbitContinuationOptions o = options();
  o.lambda_min = -0.7;
  OrbitContinuation c(p, 0, o, &floquet);
  RecordingObserver rec;
  const OrbitContinuationResult r = branch_from_two_orbits(p, c, rec);
  EXPECT_EQ(r.code, StopCode::LowerBound) << r.reason;
  ASSERT_EQ(r.located.size(), 2u);
  EXPECT_TRUE(rec.notes.empty());
  EXPECT_EQ(rec.of_kind(PointKind::PeriodDoubling).size(), 2u);
  EXPECT_TRUE(rec.of_kind(PointKind::NeimarkSacker).empty());
  const OrbitPoint& pd = r.located[0];
  // MatCont's 7 printed digits; the RK4 values to the discretisation's 1e-9
  EXPECT_NEAR(pd.lambda, 0.6303020, 5e-8);
  EXPECT_NEAR(pd.period, 6.364071, 5e-7);
  EXPECT_NEAR(pd.lambda, 0.6303020062, 2e-9);
  EXPECT_NEAR(pd.period, 6.3640713394, 2e-9);
  ASSERT_EQ(pd.multipliers.size(), 3u);
  EXPECT_NEAR(pd.multipliers[static_cast<size_t>(pd.trivial)].real(), 1.0, 1e-8);
  const double third = -std::exp(-pd.lambda * pd.period);
  int at_minus_one = 0;
  for (const auto& mu : pd.multipliers) {
    if (std::abs(mu + 1.0) < 1e-8) ++at_minus_one;
    if (std::abs(mu - third) < 1e-9) ++at_minus_one;
  }
  EXPECT_EQ(at_minus_one, 2) << "-1 and -exp(-alpha T) = " << third;
  // the mirror image
  EXPECT_NEAR(r.located[1].lambda, -pd.lambda, 2e-9);
  EXPECT_NEAR(r.located[1].period, pd.period, 2e-9);
}

// The branch's time (its seconds column and its summary) counts from the continuation's start: its
// first two orbits, corrected before run() and reported as its first rows, included. A run that
// ends at once (two orbits computed) took at least their integrations and passes.
TEST(OrbitBranch, TheBranchTimeIncludesItsFirstOrbits) {
  FunctionProblem p = adaptive_control(0.95);
  OrbitContinuationOptions o = options();
  o.max_points = 2;
  OrbitContinuation c(p, 0, o, nullptr);
  RecordingObserver rec;
  const OrbitContinuationResult r = branch_from_two_orbits(p, c, rec);
  EXPECT_EQ(r.code, StopCode::MaxSteps) << r.reason;
  const double counted = r.counts.forward_seconds + r.counts.linearised_seconds;
  EXPECT_GT(counted, 0.0);
  EXPECT_GE(r.seconds, counted);
  ASSERT_EQ(rec.points.size(), 2u);
  EXPECT_GE(rec.points[1].seconds, counted);
}

// Each orbit carries its grid check (OrbitPoint::grid_error): its own integration's largest
// SDIRK4 estimate on the grid it was computed on, the map's step_error there (the same computation:
// to rounding), and a number a new grid is recorded by (finite, not the +inf of no estimate).
TEST(OrbitBranch, AnOrbitCarriesTheErrorEstimateOfItsGrid) {
  FunctionProblem p = adaptive_control(0.95);
  OrbitContinuationOptions o = options();
  OrbitContinuation c(p, 0, o, nullptr);
  Vector u0(3), flow(3);
  u0 << 0.236, 0.0, -0.236;
  flow << 0.0, -1.0, 0.0;
  OrbitPoint a;
  ASSERT_TRUE(c.converge(u0, 2.0 * std::numbers::pi, flow, a).is_ok());
  ShootingMap map(p, 0, o.shooting);
  ASSERT_TRUE(map.integrate(a.u0, a.period, a.grid).is_ok());
  const double direct = map.step_error(o.time.relative_tolerance, o.time.absolute_tolerance);
  ASSERT_TRUE(std::isfinite(a.grid_error));
  EXPECT_NEAR(a.grid_error, direct, 1e-9 * direct);
  EXPECT_GT(a.grid_error, 0.0);
  EXPECT_LT(a.grid_error, 10.0);
}

// Branch switching at the period doubling onto the doubled branch: its orbits lie below alpha_PD,
// have twice the period there, and are not the single orbit run twice: half a period from u0 they
// are |Phi_(T/2)(u0) - u0| away from u0, which grows as sqrt(alpha_PD - alpha) (a pitchfork of the
// doubled map).
TEST(OrbitBranch, SwitchingOntoTheDoubledBranch) {
  FunctionProblem p = adaptive_control(0.66);
  FloquetAnalysis floquet;
  OrbitContinuationOptions o = options();
  o.lambda_min = 0.6;
  OrbitContinuation c(p, 0, o, &floquet);
  Vector u0(3), flow(3);
  u0 << 0.7, 0.0, -0.5;  // near the orbit at alpha = 0.66 (x max 0.75 at the doubling)
  flow << 0.0, -1.0, 0.0;
  OrbitPoint a, b;
  ASSERT_TRUE(c.converge(u0, 6.36, flow, a).is_ok());
  p.parameters().set(0, 0.65);
  ASSERT_TRUE(c.converge(a.u0, a.period, a.flow, b).is_ok());
  RecordingObserver single;
  const OrbitContinuationResult r = c.run(a, b, single);
  ASSERT_EQ(r.located.size(), 1u);
  const OrbitPoint& pd = r.located[0];
  Vector v;
  ASSERT_TRUE(c.period_doubling_vector(pd, v).is_ok());
  OrbitPoint first, second;
  ASSERT_TRUE(c.switch_period_doubling(pd, v, 0.02, first, second).is_ok());
  EXPECT_LT(second.lambda, pd.lambda);
  EXPECT_NEAR(second.period, 2.0 * pd.period, 1e-2);
  RecordingObserver doubled;
  OrbitContinuationOptions od = o;
  od.lambda_min = 0.58;
  OrbitContinuation cd(p, 0, od, &floquet);
  const OrbitContinuationResult rd = cd.run(first, second, doubled);
  EXPECT_EQ(rd.code, StopCode::LowerBound) << rd.reason;
  ShootingMap half(p, 0, o.shooting);
  std::vector<double> ratios;
  for (const BranchPoint& q : doubled.points) {
    if (q.kind == PointKind::Start) continue;
    EXPECT_LT(q.lambda, pd.lambda);
    p.parameters().set(0, q.lambda);
    const double T = q.observables[0];
    TimeOptions t = o.time;
    ASSERT_TRUE(half.integrate(q.u, 0.5 * T, record_grid(p, q.u, 0.5 * T, t)).is_ok());
    const double gap = (half.end() - q.u).norm();
    EXPECT_GT(gap, 0.05) << q.lambda;
    // the sqrt law within alpha_PD - 0.065 (the last row, past the range's lower end, lies wherever
    // the last step took it: 0.49, where the next order has moved the ratio to 1.54)
    if (pd.lambda - q.lambda <= 0.065) ratios.push_back(gap / std::sqrt(pd.lambda - q.lambda));
  }
  // measured 1.66 near the doubling to 1.61 at alpha = 0.58 (the next order of the pitchfork)
  ASSERT_GE(ratios.size(), 3u);
  for (double x : ratios) EXPECT_NEAR(x / ratios.front(), 1.0, 0.06);
}

// The range of a periodic signal from samples: cos(2 pi t) + 0.3 sin(4 pi t) on a nonuniform grid
// whose extremes fall between samples, against its range from a search on 2e6 points (1e-11). The
// samples miss it by O(h^2); the parabolas by at most max|x'''| h^3 / 12 = 70 h^3 (max|x'''| <= 843),
// and where the extremes fall decides how much less: measured 3e-5, 7e-6 and 1e-6 against the
// samples' 3e-4, 3e-4 and 1e-4.
TEST(OrbitBranch, ThePeriodicRangeRefinesTheExtremeSamples) {
  auto x = [](double t) { return std::cos(2 * std::numbers::pi * t) + 0.3 * std::sin(4 * std::numbers::pi * t); };
  double lo = 1e300, hi = -1e300;
  for (int i = 0; i <= 2000000; ++i) {
    const double v = x(i / 2000000.0);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  for (int m : {80, 160, 320}) {
    std::vector<double> t, v;
    for (int i = 0; i <= m; ++i) {
      const double s = static_cast<double>(i) / m;
      t.push_back(s + 0.1 * std::sin(2 * std::numbers::pi * s) / (2 * std::numbers::pi));  // nonuniform
      v.push_back(x(t.back()));
    }
    const double raw = (*std::max_element(v.begin(), v.end()) - *std::min_element(v.begin(), v.end())) - (hi - lo);
    const double refined = periodic_range(t, v) - (hi - lo), h = 1.1 / m;
    EXPECT_LT(std::abs(refined), 70.0 * h * h * h) << m;
    EXPECT_LT(std::abs(refined), 0.2 * std::abs(raw)) << m;
  }
}

// The multiplier counts and test functions on synthetic multipliers: the trivial one never counts;
// a real multiplier beyond -1 is a period doubling's, beyond +1 a fold's or branch point's; a
// complex pair outside the circle a Neimark-Sacker's, and a real pair whose product is 1 (a neutral
// saddle) is none.
TEST(OrbitBranch, MultiplierCountsAndTestFunctions) {
  using C = std::complex<double>;
  const std::vector<C> saddle{C(-16.8, 0), C(1.0 + 1e-9, 0), C(-1.0 / 16.8, 0)};
  const MultiplierCounts s = MultiplierCounts::of(saddle, 1);
  EXPECT_EQ(s.below_minus_one, 1);
  EXPECT_EQ(s.pairs_outside, 0);
  EXPECT_EQ(s.above_plus_one, 0);
  EXPECT_EQ(s.unstable, 1);
  EXPECT_TRUE(std::isnan(multiplier_test(saddle, 1, PointKind::NeimarkSacker)));
  EXPECT_NEAR(multiplier_test(saddle, 1, PointKind::PeriodDoubling), -1.0 / 16.8 + 1.0, 1e-15);
  const std::vector<C> torus{C(1.0, 0), C(0.3, 1.02), C(0.3, -1.02), C(1.2, 0), C(-0.9, 0)};
  const MultiplierCounts t = MultiplierCounts::of(torus, 0);
  EXPECT_EQ(t.pairs_outside, 1);
  EXPECT_EQ(t.above_plus_one, 1);
  EXPECT_EQ(t.below_minus_one, 0);
  EXPECT_EQ(t.unstable, 3);
  EXPECT_NEAR(multiplier_test(torus, 0, PointKind::NeimarkSacker), std::abs(C(0.3, 1.02)) - 1.0, 1e-15);
  EXPECT_NEAR(multiplier_test(torus, 0, PointKind::Fold), 0.2, 1e-15);
  EXPECT_NEAR(multiplier_test(torus, 0, PointKind::PeriodDoubling), 0.1, 1e-15);
}

// The period of a sampled oscillation (the start from an evolve run): a decaying transient in the
// first half is ignored, the crossings of the second half's mid level by linear interpolation give
// the period to O(h^2) per crossing (h = T / 40 here: 1e-3 allowed, measured below 1e-4 since the
// errors of the crossings average out); too few crossings, or a constant signal, give nothing.
TEST(OrbitBranch, OscillationPeriodFromSamples) {
  const double T = 2.7;
  std::vector<double> t, y;
  for (double s = 0.0; s <= 12.0 * T; s += (T / 40.0) * (1.0 + 0.3 * std::sin(7.0 * s))) {
    t.push_back(s);
    y.push_back(5.0 + std::sin(2.0 * std::numbers::pi * s / T) + 0.2 * std::sin(4.0 * std::numbers::pi * s / T) +
                3.0 * std::exp(-s));
  }
  const std::optional<double> p = oscillation_period(t, y);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(*p / T, 1.0, 1e-3);
  const std::vector<double> short_t(t.begin(), t.begin() + 150), short_y(y.begin(), y.begin() + 150);  // 3.75 T
  EXPECT_FALSE(oscillation_period(short_t, short_y).has_value());
  EXPECT_FALSE(oscillation_period(t, std::vector<double>(t.size(), 1.0)).has_value());
}

// An orbit branch computes as many multipliers as its rows store ([orbit] multipliers; the
// default FloquetOptions' 8 made Arnoldi converge two more than the 6 stored), and at least two.
TEST(OrbitBranch, TheBranchComputesTheMultipliersItStores) {
  EXPECT_EQ(FloquetAnalysis::for_branch(6).count(), 6);
  EXPECT_EQ(FloquetAnalysis::for_branch(12).count(), 12);
  EXPECT_EQ(FloquetAnalysis::for_branch(0).count(), FloquetAnalysis::kLeast);
}
