// Linear stability along branches (stability/StabilityAnalysis driven by the continuation
// engine): eigenvalues crossing zero at a fold and at pitchforks with known locations, a Hopf
// point with a known location and frequency, branch switching onto the bifurcated branch, and
// the spectrum of the collapsible channel on a coarse mesh.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <iostream>

#include "continuation/Continuation.hpp"
#include "core/Newton.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Brusselator1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "problems/channel/CollapsibleChannelProblem.hpp"
#include "stability/StabilityAnalysis.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

StabilityOptions stability(int count, std::vector<std::complex<double>> shifts = {0.0}, int every = 1) {
  StabilityOptions s;
  s.enabled = true;
  s.count = count;
  s.shifts = std::move(shifts);
  s.every = every;
  return s;
}

struct Traced {
  ContinuationResult result;
  test::RecordingObserver rec;
  std::vector<std::string> columns;  // of the analysis
  long eigen_factorisations = 0;     // of J - s B by the analysis itself
};

// Traces from the problem's initial guess (or switches branches at *switch_at) with the spectrum
// of `count` eigenvalues at every point.
Traced trace_with_stability(Problem& p, const ContinuationOptions& o, int count, const BranchPoint* switch_at = nullptr,
                            std::vector<std::complex<double>> shifts = {0.0}, int every = 1) {
  Continuation cont(p, o);
  StabilityAnalysis analysis(stability(count, std::move(shifts), every));
  cont.set_analysis(&analysis);
  Traced t;
  t.columns = analysis.column_names();
  t.result = switch_at ? cont.switch_branch(*switch_at, +1, t.rec) : cont.run(p.initial_guess(), t.rec);
  t.eigen_factorisations = analysis.factorisations();
  return t;
}

int column(const std::vector<std::string>& names, const std::string& n) {
  return static_cast<int>(std::find(names.begin(), names.end(), n) - names.begin());
}

// The trivial branch u = 0 of the pitchfork problem from lambda = 1 to 45 (through its first two
// branch points), found by the spectrum alone (no determinant).
ContinuationOptions pitchfork_trivial_branch() {
  ContinuationOptions o = test::pitchfork_trivial_options();
  o.events.branch_points = false;
  o.state_scale = 1.0;
  return o;
}

// The uniform Brusselator state from 1.7 below its Hopf point b = 1 + a^2 to 1.5 above it.
Brusselator1DOptions brusselator(double a) {
  Brusselator1DOptions bo;
  bo.intervals = 32;
  bo.a = a;
  bo.b = 1.0 + a * a - 1.7;
  return bo;
}
ContinuationOptions brusselator_branch(double a) {
  ContinuationOptions o;
  o.parameter = "b";
  o.stop.upper = 1.0 + a * a + 1.5;
  o.step.initial = 0.1;
  o.step.max = 0.5;
  o.events.tolerance = 1e-10;
  return o;
}

}  // namespace

// Bratu: the stable lower branch turns at the fold into the unstable upper one. The count of
// unstable eigenvalues changes 0 -> 1 there, the change is classified as the fold (the parameter
// turns) and merged with the fold the tangent located; its eigenvalue nearest zero is zero to the
// accuracy of the located point.
TEST(Stability, BratuFoldIsWhereAnEigenvalueCrossesZero) {
  Bratu1DProblem p(64, 0.0);
  const Traced t = trace_with_stability(p, test::bratu_fold_options("u_mid", 4.0), 4);
  const auto& rec = t.rec;
  ASSERT_EQ(t.result.code, StopCode::StopObservable) << t.result.reason;
  const auto folds = rec.of_kind(PointKind::Fold);
  ASSERT_EQ(folds.size(), 1u);
  const BranchPoint& f = *folds[0];
  EXPECT_NE(f.label.find("eigenvalue crosses zero"), std::string::npos) << f.label;
  EXPECT_NE(f.label.find("0 -> 1"), std::string::npos) << f.label;
  EXPECT_TRUE(rec.of_kind(PointKind::BranchPoint).empty());
  const double s1 = f.analysis[column(t.columns, "sigma1_re")], s2 = f.analysis[column(t.columns, "sigma2_re")];
  std::cout << std::setprecision(12) << "fold at lambda = " << f.lambda << ": sigma1 = " << s1 << ", sigma2 = " << s2
            << "\n";
  // located to 1e-12 in lambda, so to about 1e-6 along the branch: sigma1 = O(1e-6) sigma2
  EXPECT_LT(std::abs(s1), 1e-5 * std::abs(s2));
  // lower branch stable, upper branch unstable
  for (const auto& q : rec.points) {
    if (q.count < 0 || q.kind == PointKind::Fold) continue;
    EXPECT_EQ(q.count, q.s < f.s ? 0 : 1) << "row " << q.index;
  }
}

// u'' + lambda u - u^3 = 0: the trivial branch loses stability at the discrete eigenvalues
// lambda_k = (4/h^2) sin^2(k pi h/2) -> (k pi)^2 (second order in h). Found by the spectrum alone
// (no determinant), classified as branch points (the parameter does not turn), located to 1e-8.
TEST(Stability, PitchforkBranchPointsConvergeAndTheSwitchedBranchBifurcates) {
  std::vector<double> err1;
  for (int n : {16, 32, 64}) {
    Pitchfork1DProblem p(n, 1.0);
    ContinuationOptions o = pitchfork_trivial_branch();
    const Traced t = trace_with_stability(p, o, 4);
    const auto& rec = t.rec;
    ASSERT_EQ(t.result.code, StopCode::UpperBound) << t.result.reason;
    const auto bps = rec.of_kind(PointKind::BranchPoint);
    ASSERT_EQ(bps.size(), 2u) << "n = " << n;
    EXPECT_TRUE(rec.of_kind(PointKind::Fold).empty());
    for (int k = 1; k <= 2; ++k) {
      const double exact = Pitchfork1DProblem::branch_point(k, n);
      EXPECT_NEAR(bps[k - 1]->lambda, exact, 1e-8) << "n = " << n << ", k = " << k;
      // the count changes there (at the located point itself it may be either)
      EXPECT_NE(bps[k - 1]->label.find(std::to_string(k - 1) + " -> " + std::to_string(k)), std::string::npos)
          << bps[k - 1]->label;
    }
    err1.push_back(std::abs(bps[0]->lambda - M_PI * M_PI));
    std::cout << std::setprecision(12) << "n = " << n << ": branch points " << bps[0]->lambda << ", " << bps[1]->lambda
              << "; |lambda_1 - pi^2| = " << err1.back() << "\n";

    if (n != 64) continue;
    // switching at the first branch point: the new branch leaves u = 0, bends to lambda > lambda_1
    // (supercritical) and is stable
    o.stop.upper = 20.0;
    const Traced t2 = trace_with_stability(p, o, 4, bps[0]);
    const auto& rec2 = t2.rec;
    ASSERT_EQ(t2.result.code, StopCode::UpperBound) << t2.result.reason;
    EXPECT_EQ(rec2.points.back().lambda, 20.0);
    ASSERT_GT(rec2.points.size(), 5u);
    std::vector<std::string> obs = p.observable_names();
    const int inorm = column(obs, "u_norm");
    for (size_t i = 1; i < rec2.points.size(); ++i) {
      const BranchPoint& q = rec2.points[i];
      EXPECT_GT(q.observables[inorm], 1e-3) << "row " << q.index;
      EXPECT_GT(q.lambda, bps[0]->lambda - 1e-8) << "row " << q.index;
      EXPECT_EQ(q.count, 0) << "row " << q.index;
    }
    // near the bifurcation u ~ A sin(pi x) with A^2 = 4 (lambda - lambda_1) / 3 (projecting the cubic
    // on sin: int sin^4 / int sin^2 = 3/4), so u_norm^2 = A^2 / 2 = 2 (lambda - lambda_1) / 3
    const BranchPoint& near = rec2.points[1];
    const double ratio = near.observables[inorm] * near.observables[inorm] / (near.lambda - bps[0]->lambda);
    std::cout << "first point of the switched branch: u_norm^2 / (lambda - lambda_1) = " << ratio << "\n";
    EXPECT_NEAR(ratio, 2.0 / 3.0, 0.01);  // O(lambda - lambda_1) correction: 5e-5 at this first point
  }
  // second order: the error falls by 4 per halving of h
  EXPECT_NEAR(err1[0] / err1[1], 4.0, 0.1);
  EXPECT_NEAR(err1[1] / err1[2], 4.0, 0.1);
}

// Brusselator, no flux, equal diffusivities: the uniform state loses stability through a Hopf
// bifurcation of the uniform mode at b = 1 + a^2 with frequency a (exact also on the grid).
TEST(Stability, BrusselatorHopfLocatedWithItsFrequency) {
  for (double a : {2.0, 1.3}) {
    Brusselator1DProblem p(brusselator(a));
    const Traced t = trace_with_stability(p, brusselator_branch(a), 6);
    const auto& rec = t.rec;
    ASSERT_EQ(t.result.code, StopCode::UpperBound) << t.result.reason;
    const auto hopf = rec.of_kind(PointKind::Hopf);
    ASSERT_EQ(hopf.size(), 1u) << "a = " << a;
    const BranchPoint& h = *hopf[0];
    std::cout << std::setprecision(12) << "a = " << a << ": Hopf at b = " << h.lambda
              << ", omega = " << std::abs(h.critical_imag) << " (" << h.label << ")\n";
    EXPECT_NEAR(h.lambda, 1.0 + a * a, 1e-8);
    EXPECT_NEAR(std::abs(h.critical_imag), a, 1e-6);
    EXPECT_NE(h.label.find("0 -> 2"), std::string::npos) << h.label;
    EXPECT_EQ(h.label.rfind("omega = ", 0), 0u) << h.label;
    EXPECT_TRUE(rec.of_kind(PointKind::Fold).empty());
    EXPECT_TRUE(rec.of_kind(PointKind::BranchPoint).empty());
    // the critical pair sits on the axis (|Re sigma| ~ 1e-9 or below at the located b) and counts as
    // neutral in the table: 0 unstable there, 2 at the end (b = 1 + a^2 + 1.5, Re sigma = -0.75)
    const size_t iu = 2 * 6;  // columns: sigma1_re, sigma1_im, ..., sigma6_im, unstable
    ASSERT_GT(h.analysis.size(), iu);
    EXPECT_EQ(h.analysis[iu], 0.0);
    EXPECT_EQ(rec.points.back().analysis[iu], 2.0);
    // the critical eigenvector (complex) is stored with the point and is an eigenvector of (J, B)
    ASSERT_EQ(h.critical_re.size(), p.size());
  }
}

// The collapsible channel on a coarse mesh at the reference parameters. In its physical form (the
// default) even Newtonian Stokes flow has finite eigenvalues: the wall relaxing through the
// viscous fluid. In the fixed-wall form Newtonian Stokes flow has no dynamics (B = 0): no finite
// eigenvalue, never an infinite one passed off as finite. With inertia (Re = 1) and for Oldroyd-B
// (Wi = 0.1) the eigenvalues nearest zero come with residuals below the tolerance and the states
// are stable.
TEST(Stability, CollapsibleChannelSpectraOnACoarseMesh) {
  struct Case {
    const char* name;
    FluidModel model;
    double Re;
    bool moving_wall;
  };
  for (const Case c : {Case{"newtonian Re = 0", FluidModel::Newtonian, 0.0, true},
                       Case{"newtonian Re = 0, fixed wall", FluidModel::Newtonian, 0.0, false},
                       Case{"newtonian Re = 1", FluidModel::Newtonian, 1.0, true},
                       Case{"newtonian Re = 1, fixed wall", FluidModel::Newtonian, 1.0, false},
                       Case{"oldroyd-b", FluidModel::OldroydB, 0.0, true},
                       Case{"oldroyd-b, fixed wall", FluidModel::OldroydB, 0.0, false}}) {
    SCOPED_TRACE(c.name);
    CollapsibleOptions o;
    o.moving_wall_dynamics = c.moving_wall;
    o.mesh.name = "custom";
    o.mesh.nx_upstream = 3;
    o.mesh.nx_deformable = 6;
    o.mesh.nx_downstream = 3;
    o.mesh.ny_fluid = 3;
    o.mesh.ny_solid = 1;
    o.Gamma = 4.95e-5;
    o.Pe = 0.04;
    o.fluid.model = c.model;
    o.fluid.Wi = 0.1;
    o.fluid.Re = c.Re;
    o.fluid.inertia = c.Re > 0;
    CollapsibleChannelProblem problem(o);
    Vector u = problem.initial_guess();
    SparseLUOptions lu;
    lu.ordering = SparseLUOptions::Ordering::Metis;
    NewtonSolver newton(problem, {}, lu);
    ASSERT_TRUE(newton.solve(u).converged());
    StabilityOptions so = stability(6);
    StabilityAnalysis analysis(so, lu);
    PointAnalysisResult res;
    const Status st = analysis.analyse(problem, u, res);
    ASSERT_TRUE(st.is_ok()) << st.describe();
    if (c.Re == 0 && c.model == FluidModel::Newtonian && !c.moving_wall) {
      EXPECT_EQ(res.count, 0);
      EXPECT_TRUE(analysis.spectrum().empty());
      EXPECT_TRUE(std::isnan(res.columns[0]));
      continue;
    }
    ASSERT_GE(analysis.spectrum().size(), 6u);
    EXPECT_EQ(res.count, 0);
    for (const EigenPair& e : analysis.spectrum()) {
      std::cout << c.name << ": sigma = " << e.value << ", residual " << e.residual << "\n";
      EXPECT_LT(e.residual, so.residual_tolerance);
      EXPECT_GT(e.value.real(), 0.0);
      EXPECT_TRUE(std::isfinite(std::abs(e.value)));
    }
  }
}

// The same Hopf point found through a complex shift alone: s = 1.9 i next to the crossing pair
// (omega = a = 2), two eigenvalues per point, complex arithmetic (znaupd on a complex
// factorisation of J - s B) at every point of the branch. The pair found is the crossing one and
// its conjugate is completed, so the count still changes 0 -> 2 and the location agrees with the
// exact b = 1 + a^2.
TEST(Stability, BrusselatorHopfThroughAComplexShift) {
  const double a = 2.0;
  Brusselator1DProblem p(brusselator(a));
  const Traced t = trace_with_stability(p, brusselator_branch(a), 2, nullptr, {std::complex<double>(0.0, 1.9)});
  ASSERT_EQ(t.result.code, StopCode::UpperBound) << t.result.reason;
  const auto hopf = t.rec.of_kind(PointKind::Hopf);
  ASSERT_EQ(hopf.size(), 1u);
  const BranchPoint& h = *hopf[0];
  std::cout << std::setprecision(12) << "complex shift 1.9i: Hopf at b = " << h.lambda
            << ", omega = " << std::abs(h.critical_imag) << " (" << h.label << ")\n";
  EXPECT_NEAR(h.lambda, 1.0 + a * a, 1e-8);
  EXPECT_NEAR(std::abs(h.critical_imag), a, 1e-6);
  EXPECT_NE(h.label.find("0 -> 2"), std::string::npos) << h.label;
  // the columns hold the conjugate pair (sigma1, sigma2) = (x - i omega, x + i omega)
  const double im1 = h.analysis[column(t.columns, "sigma1_im")], im2 = h.analysis[column(t.columns, "sigma2_im")];
  EXPECT_NEAR(im1, -a, 1e-6);
  EXPECT_NEAR(im2, a, 1e-6);
}

// Spectra only every 5th point: a change of the count is bracketed by bisection over the accepted
// points since the last spectrum (about log2(5) more spectra) and located as with every point.
// Pitchfork: both branch points to 1e-8 at their discrete values; Brusselator: the Hopf point at
// b = 1 + a^2 with omega = a. Far fewer spectra than points.
TEST(Stability, EveryNthPointStillLocatesByBisection) {
  {
    Pitchfork1DProblem p(32, 1.0);
    const Traced t = trace_with_stability(p, pitchfork_trivial_branch(), 4, nullptr, {0.0}, 5);
    ASSERT_EQ(t.result.code, StopCode::UpperBound) << t.result.reason;
    const auto bps = t.rec.of_kind(PointKind::BranchPoint);
    ASSERT_EQ(bps.size(), 2u);
    for (int k = 1; k <= 2; ++k) {
      EXPECT_NEAR(bps[k - 1]->lambda, Pitchfork1DProblem::branch_point(k, 32), 1e-8) << "k = " << k;
      EXPECT_NE(bps[k - 1]->label.find(std::to_string(k - 1) + " -> " + std::to_string(k)), std::string::npos)
          << bps[k - 1]->label;
    }
    EXPECT_NE(bps[0]->label.find("bisection"), std::string::npos) << bps[0]->label;
    const long analysed =
        std::count_if(t.rec.points.begin(), t.rec.points.end(), [](const BranchPoint& q) { return q.analysed; });
    std::cout << "pitchfork, every 5: " << analysed << " of " << t.rec.points.size() << " rows analysed\n";
    EXPECT_LT(analysed, static_cast<long>(t.rec.points.size()) / 2);
  }
  {
    const double a = 2.0;
    Brusselator1DProblem p(brusselator(a));
    ContinuationOptions o = brusselator_branch(a);
    o.step.initial = 0.05;  // shorter steps: several points between two spectra before the Hopf
    o.step.max = 0.1;
    const Traced t = trace_with_stability(p, o, 6, nullptr, {0.0}, 5);
    ASSERT_EQ(t.result.code, StopCode::UpperBound) << t.result.reason;
    const auto hopf = t.rec.of_kind(PointKind::Hopf);
    ASSERT_EQ(hopf.size(), 1u);
    EXPECT_NEAR(hopf[0]->lambda, 1.0 + a * a, 1e-8);
    EXPECT_NEAR(std::abs(hopf[0]->critical_imag), a, 1e-6);
    EXPECT_NE(hopf[0]->label.find("0 -> 2"), std::string::npos) << hopf[0]->label;
  }
}

// With block elimination a point about to be analysed gets J's factorisation at itself (exact
// tangent), and the spectrum at s = 0 solves with it instead of factorising J again: the same
// branch points, and at least one eigen-solver factorisation fewer per analysed accepted point.
TEST(Stability, SpectrumReusesTheContinuationsFactorisation) {
  std::vector<Traced> runs;
  for (bool block : {false, true}) {
    Pitchfork1DProblem p(32, 1.0);
    ContinuationOptions o = pitchfork_trivial_branch();
    o.corrector.block_elimination = block;
    runs.push_back(trace_with_stability(p, o, 4));
    ASSERT_EQ(runs.back().result.code, StopCode::UpperBound) << runs.back().result.reason;
  }
  const auto full = runs[0].rec.of_kind(PointKind::BranchPoint), block = runs[1].rec.of_kind(PointKind::BranchPoint);
  ASSERT_EQ(full.size(), 2u);
  ASSERT_EQ(block.size(), 2u);
  for (size_t k = 0; k < 2; ++k) EXPECT_NEAR(block[k]->lambda, full[k]->lambda, 1e-9);
  const long accepted = std::count_if(runs[1].rec.points.begin(), runs[1].rec.points.end(), [](const BranchPoint& q) {
    return q.analysed && (q.kind == PointKind::Regular || q.kind == PointKind::Start);
  });
  std::cout << "eigen-solver factorisations: full " << runs[0].eigen_factorisations << ", block "
            << runs[1].eigen_factorisations << " (" << accepted << " accepted points analysed)\n";
  EXPECT_LE(runs[1].eigen_factorisations, runs[0].eigen_factorisations - accepted);
}

// Turing modes of the Brusselator (D_v = 10 D_u): on every grid the uniform state's mode k (cosine,
// mu_k = (4/h^2) sin^2(k pi h / 2L) of the discrete -d^2/dx^2) has a real eigenvalue through zero
// where det of its 2 x 2 linearisation vanishes, b_k = (1 + D_u mu_k)(a^2 + D_v mu_k) / (D_v mu_k).
// On (0, 20) with 40 intervals seven modes cross between b = 2.5 and 3.6, 0.065 apart at the
// closest.
namespace {

Brusselator1DOptions turing_brusselator() {
  Brusselator1DOptions bo;
  bo.intervals = 40;
  bo.length = 20.0;
  bo.a = 2.0;
  bo.b = 2.5;
  bo.D_u = 1.0;
  bo.D_v = 10.0;
  return bo;
}

std::vector<double> turing_crossings(const Brusselator1DOptions& bo, double below) {
  std::vector<double> b;
  const double h = bo.length / bo.intervals;
  for (int k = 1; k <= bo.intervals; ++k) {
    const double mu = 4.0 / (h * h) * std::pow(std::sin(k * M_PI * h / (2.0 * bo.length)), 2);
    const double bk = (1.0 + bo.D_u * mu) * (bo.a * bo.a + bo.D_v * mu) / (bo.D_v * mu);
    if (bk > bo.b && bk < below) b.push_back(bk);
  }
  std::sort(b.begin(), b.end());
  return b;
}

Traced trace_turing(double max_step) {
  Brusselator1DProblem p(turing_brusselator());
  ContinuationOptions o;
  o.parameter = "b";
  o.stop.upper = 3.6;
  o.step.initial = 0.1;
  o.step.max = max_step;
  o.events.tolerance = 1e-10;
  return trace_with_stability(p, o, 2);
}

std::vector<const BranchPoint*> branch_points(const Traced& t) {
  std::vector<const BranchPoint*> b;
  for (const auto& q : t.rec.points)
    if (q.kind == PointKind::BranchPoint) b.push_back(&q);
  return b;
}

}  // namespace

// Steps of up to 0.1: two crossings within one step (2.666 and 2.731), where the determinant's sign
// sees none. Each crossing is its own branch point, at its b_k to 1e-8, the count rising by one at
// each; with 2 eigenvalues asked for, the set grows so that the modes that crossed stay counted as
// they move away from the shift (without it the count falls back, 2 -> 1 -> 0).
TEST(Stability, TuringModesCrossingWithinOneStepAreEachLocated) {
  const std::vector<double> expected = turing_crossings(turing_brusselator(), 3.6);
  ASSERT_EQ(expected.size(), 7u);
  const Traced t = trace_turing(0.1);
  ASSERT_EQ(t.result.code, StopCode::UpperBound) << t.result.reason;
  const auto crossings = branch_points(t);
  ASSERT_EQ(crossings.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(crossings[i]->lambda, expected[i], 1e-8) << i;
    EXPECT_NE(crossings[i]->label.find(fmt::format("{} -> {}", i, i + 1)), std::string::npos) << crossings[i]->label;
  }
  // every ordinary point counts the modes that crossed before it
  for (const auto& q : t.rec.points) {
    if (q.kind != PointKind::Regular || q.count < 0) continue;
    const auto before = std::count_if(expected.begin(), expected.end(), [&](double bk) { return bk < q.lambda; });
    EXPECT_EQ(q.count, before) << "b = " << q.lambda;
  }
}

// Steps of up to 0.5 with 2 eigenvalues: within one step two modes cross and move farther from the
// shift than stable ones that have not crossed yet, out of the set before anything shows them.
// Where the set grows, the point before is analysed again, and the crossings it missed are said
// (not located, and not located wrongly): every located crossing is at some b_k to 1e-8, and
// together with those said they account for all seven.
TEST(Stability, CrossingsASetTooSmallMissedAreSaidNotMislocated) {
  const std::vector<double> expected = turing_crossings(turing_brusselator(), 3.6);
  const Traced t = trace_turing(0.5);
  ASSERT_EQ(t.result.code, StopCode::UpperBound) << t.result.reason;
  const auto crossings = branch_points(t);
  for (const BranchPoint* c : crossings)
    EXPECT_TRUE(
        std::any_of(expected.begin(), expected.end(), [&](double bk) { return std::abs(bk - c->lambda) < 1e-8; }))
        << "a crossing located at b = " << c->lambda << ": " << c->label;
  // the crossings said instead: a count a point had wrong (less those of its changes the
  // determinant located), or a change the locator could not reach
  int missed = 0;
  for (const std::string& n : t.rec.notes) {
    int has = 0, had = 0;
    if (std::sscanf(n.c_str(), "row %*d has %d unstable eigenvalues, not %d", &has, &had) == 2) {
      const size_t part = n.find("); ");
      int unlocated = 0, of = 0;
      if (part != std::string::npos && std::sscanf(n.c_str() + part, "); %d of its %d changes", &unlocated, &of) == 2) {
        EXPECT_EQ(of, has - had) << n;
        missed += unlocated;
      } else {
        missed += has - had;
      }
    }
    if (std::sscanf(n.c_str(), "event 'unstable eigenvalues %d -> %d' detected", &had, &has) == 2) missed += has - had;
  }
  EXPECT_GT(missed, 0);
  EXPECT_EQ(static_cast<int>(crossings.size()) + missed, static_cast<int>(expected.size()));
}

// A diagonal problem, u = 0 for every lambda, eigenvalues sigma_A = 0.05 - lambda (through zero at
// 0.05 and on away from the shift) and 0.1, 0.2, ..., 1.1 (stable, fixed), 2 computed. From
// lambda = 0.1 (A unstable, inside the set) one step of 0.5 carries A out of the set: the count
// falls 1 -> 0 with nothing crossing zero. That is no stability change and is not located as one
// (a branch point "eigenvalue crosses zero" where no eigenvalue is near zero): the set is computed
// wider until it holds A again, and A stays counted.
TEST(Stability, AnEigenvalueLeavingTheSetIsNoCrossing) {
  const int n = 12;
  const auto d = [](double lambda) {
    Vector v(12);
    v << 0.05 - lambda, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1;
    return v;
  };
  test::FunctionProblem p(
      "leaving", n, {{"lambda", 0.1}},
      [d](const Vector& u, const Vector& q) { return Vector(d(q[0]).cwiseProduct(u)); },
      [d](const Vector&, const Vector& q) { return Eigen::MatrixXd(d(q[0]).asDiagonal()); },
      [](int, const Vector& u, const Vector&) {
        Vector dF = Vector::Zero(u.size());
        dF[0] = -u[0];
        return dF;
      });
  ContinuationOptions o;
  o.parameter = "lambda";
  o.stop.upper = 1.0;
  o.state_scale = 1.0;
  o.step.initial = 0.5;
  o.step.max = 0.5;
  o.events.branch_points = false;
  const Traced t = trace_with_stability(p, o, 2);
  ASSERT_EQ(t.result.code, StopCode::UpperBound) << t.result.reason;
  for (const std::string& note : t.rec.notes) EXPECT_EQ(note.find("not located"), std::string::npos) << note;
  for (const auto& q : t.rec.points)
    EXPECT_TRUE(q.kind != PointKind::BranchPoint && q.kind != PointKind::Fold && q.kind != PointKind::Hopf)
        << "a stability change located at lambda = " << q.lambda << ": " << q.label;
  // A stays counted: every point beyond its crossing has it among the unstable ones
  for (const auto& q : t.rec.points) {
    if (q.count < 0) continue;
    EXPECT_EQ(q.count, 1) << "lambda = " << q.lambda;
  }
}
