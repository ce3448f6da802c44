// Newton's method: quadratic convergence (residual history printed to the test log), the line
// search, and failures reported as statuses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include "core/ConvergenceTest.hpp"
#include "core/Newton.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Bratu2DProblem.hpp"
#include "problems/channel/ChannelProblem.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

std::vector<double> residual_history(const NewtonResult& res, const char* label) {
  std::vector<double> r;
  std::cout << label << " residual history:";
  for (const auto& it : res.history) {
    r.push_back(it.residual_norm);
    std::cout << " " << it.residual_norm;
  }
  r.push_back(res.residual_norm);
  std::cout << " -> " << res.residual_norm << "\n";
  return r;
}

// Quadratic convergence: in the asymptotic regime (residual below 10% of the first one) and
// above rounding (100x the final residual), r_{k+1} = C r_k^2 with C roughly constant. A
// linearly convergent iteration has r_{k+1} / r_k^2 growing like 1 / r_k, i.e. by orders of
// magnitude over these steps, so a spread of C within a factor 10 cannot come from it.
void expect_quadratic(const std::vector<double>& r) {
  std::vector<double> C;
  for (size_t k = 0; k + 1 < r.size(); ++k) {
    if (r[k] > 0.1 * r[0] || r[k + 1] < 100 * r.back()) continue;
    C.push_back(r[k + 1] / (r[k] * r[k]));
    std::cout << "  r_{k+1}/r_k^2 = " << C.back() << ", observed order "
              << (k > 0 ? std::log(r[k + 1] / r[k]) / std::log(r[k] / r[k - 1]) : NAN) << "\n";
  }
  ASSERT_GE(C.size(), 2u) << "too few asymptotic steps to judge the order";
  EXPECT_LT(*std::max_element(C.begin(), C.end()) / *std::min_element(C.begin(), C.end()), 10.0);
}

// The solution to a tolerance above the rounding floor (1e-11), the reference for solves that
// stop at the floor.
Vector solved_to_reachable_tolerance(Problem& problem) {
  NewtonOptions reachable;
  reachable.residual_tolerance = 1e-11;
  NewtonSolver solver(problem, reachable);
  Vector u = problem.initial_guess();
  EXPECT_TRUE(solver.solve(u).converged());
  return u;
}

// A tolerance of 1e-15: unreachable, but the floor is within 1e3 of it; no help from the
// small-update rule.
NewtonOptions below_the_floor() {
  NewtonOptions o;
  o.update_tolerance = 0.0;
  o.residual_tolerance = 1e-15;
  return o;
}

}  // namespace

TEST(Newton, ConvergesQuadraticallyOnBratu2D) {
  Bratu2DProblem problem(8, 6.5);  // close to the fold at 6.808: strongly nonlinear
  NewtonOptions opt;
  opt.chord_rate = 0.0;  // Newton's own iteration (the chord's final phase is linear)
  opt.residual_tolerance = 1e-13;
  NewtonSolver newton(problem, opt);
  Vector u = problem.initial_guess();
  const NewtonResult res = newton.solve(u);
  ASSERT_TRUE(res.converged()) << res.status.describe();
  expect_quadratic(residual_history(res, "bratu2d"));
  // one symbolic analysis, made here or taken from an identical earlier one, reused throughout
  EXPECT_EQ(newton.lu().statistics().analyses + newton.lu().statistics().analyses_reused, 1);
}

TEST(Newton, ConvergesQuadraticallyOnNavierStokes) {
  ChannelOptions o;
  o.mesh = ChannelMeshSpec::preset("M1");
  o.fluid.Re = 50.0;
  o.Gamma = 1.0;
  o.fluid.inertia = true;
  ChannelProblem problem(o);
  Vector u = problem.initial_guess();
  // a large swirl on top of Poiseuille flow makes the convective term matter
  const int fv = problem.dofs().field_index("velocity");
  for (int n = 0; n < problem.mesh().num_nodes(); ++n) {
    const auto& p = problem.mesh().node(n);
    const double bump = std::sin(M_PI * p[1]) * std::sin(M_PI * p[0] / 19.0);
    u[problem.dofs().node_dof(fv, n, 0)] += 2.0 * bump;
    u[problem.dofs().node_dof(fv, n, 1)] -= 3.0 * bump;
  }
  NewtonOptions opt;
  opt.chord_rate = 0.0;  // Newton's own iteration
  opt.residual_tolerance = 1e-13;
  NewtonSolver newton(problem, opt);
  const NewtonResult res = newton.solve(u);
  ASSERT_TRUE(res.converged()) << res.status.describe();
  expect_quadratic(residual_history(res, "navier-stokes Re=50"));
}

namespace {

// F_i = atan(u_i - i): full Newton steps diverge from |u_i - i| > 1.39 (the classic example),
// damped steps converge.
class ArctanProblem final : public Problem {
 public:
  explicit ArctanProblem(int n) : pattern_(n, n) {
    pattern_.setIdentity();
    pattern_.makeCompressed();
    params_.add("shift", 0.0, "unused");
  }
  std::string name() const override { return "arctan"; }
  int size() const override { return static_cast<int>(pattern_.rows()); }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override {
    F.resize(size());
    for (int i = 0; i < size(); ++i) F[i] = std::atan(u[i] - i);
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    for (int i = 0; i < size(); ++i) J.coeffRef(i, i) = 1.0 / (1.0 + (u[i] - i) * (u[i] - i));
    return {};
  }
  Vector initial_guess() override { return Vector::Zero(size()); }
  SolutionFields fields(const Vector&) const override { return {}; }

 private:
  SparseMatrix pattern_;
  ParameterSet params_;
};

}  // namespace

TEST(Newton, LineSearchRescuesAPoorStart) {
  ArctanProblem problem(3);
  Vector start(3);
  start << 1.5, 1.0 - 2.0, 2.0 + 3.0;  // offsets 1.5, -2, 3 from the roots 0, 1, 2
  NewtonOptions full;
  full.line_search = false;
  full.max_iterations = 30;
  Vector u = start;
  const NewtonResult undamped = NewtonSolver(problem, full).solve(u);
  EXPECT_FALSE(undamped.converged());  // plain Newton diverges from here...
  u = start;
  NewtonOptions damped;
  damped.max_iterations = 30;
  const NewtonResult res = NewtonSolver(problem, damped).solve(u);
  ASSERT_TRUE(res.converged()) << res.status.describe();  // ... the line search brings it home
  bool shortened = false;
  for (const auto& it : res.history) shortened |= it.step_length < 1.0;
  EXPECT_TRUE(shortened);
  // |atan(x)| <= 1e-10 (the residual tolerance) means |x| <= 1e-10
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(u[i], i, 1e-10);
}

TEST(Newton, FailuresAreStatuses) {
  // no solution beyond the fold: Newton must stop with a reason, not crash or loop
  Bratu1DProblem problem(32, 4.0);
  Vector u = problem.initial_guess();
  NewtonOptions opt;
  opt.max_iterations = 15;
  NewtonSolver newton(problem, opt);
  const NewtonResult res = newton.solve(u);
  EXPECT_FALSE(res.converged());
  EXPECT_FALSE(res.status.message().empty());
  EXPECT_TRUE(u.allFinite());  // the last accepted iterate is kept
  // a non-finite start is reported as such
  Vector bad = Vector::Constant(problem.size(), 800.0);
  const NewtonResult nf = newton.solve(bad);
  EXPECT_EQ(nf.status.code(), StatusCode::NotFinite);
}

// A tolerance below the rounding floor of the problem: once no damped step reduces a residual
// within 1e3 of the tolerance, Newton reports convergence at that floor (and the solution is the
// one a reachable tolerance gives). Far below it (1e-18) the floor is the problem's own, estimated
// from its Jacobian (eps max_i sum_j |J_ij| |u_j|, ConvergenceTest): converged there too, flagged,
// with the same solution; it was a failure while the floor was only looked for within 1e3 of the
// tolerance.
TEST(Newton, StopsAtTheRoundingFloor) {
  Bratu1DProblem problem(64, 2.0);  // its residual floor is about 3e-13 (1/h^2 = 4096 times rounding)
  const Vector ref = solved_to_reachable_tolerance(problem);
  NewtonOptions below = below_the_floor();
  NewtonSolver newton(problem, below);
  Vector u = problem.initial_guess();
  const NewtonResult res = newton.solve(u);
  std::cout << "tolerance 1e-15: final |F| = " << res.residual_norm << " after " << res.iterations << " iterations\n";
  ASSERT_TRUE(res.converged()) << res.status.describe();
  EXPECT_TRUE(res.at_rounding_floor);
  EXPECT_GT(res.residual_norm, 1e-15);
  EXPECT_LE(res.residual_norm, 1e-12);
  EXPECT_LT((u - ref).cwiseAbs().maxCoeff(), 1e-10);

  below.residual_tolerance = 1e-18;
  NewtonSolver strict(problem, below);
  Vector w = problem.initial_guess();
  const NewtonResult far = strict.solve(w);
  Vector F;
  SparseMatrix J;
  problem.jacobian(w, F, J);
  const double floor = rounding_floor(J, w);
  std::cout << "tolerance 1e-18: " << far.status.describe() << ", |F| = " << far.residual_norm << ", estimated floor "
            << floor << "\n";
  ASSERT_TRUE(far.converged()) << far.status.describe();
  EXPECT_TRUE(far.at_rounding_floor);
  EXPECT_LE(far.residual_norm, floor);
  EXPECT_LT((w - ref).cwiseAbs().maxCoeff(), 1e-10);
}

// chord_rate: once a full step has cut |F| by the rate, later iterations keep its factorisation
// while each cuts |F| by the rate. Near Bratu's fold, to 1e-13: the same solution (to the
// tolerance over the Jacobian's smallest singular scale) with fewer factorisations.
TEST(Newton, ChordRateSavesFactorisationsInTheFinalPhase) {
  Bratu2DProblem problem(8, 6.5);
  NewtonOptions newton_only;
  newton_only.chord_rate = 0.0;
  newton_only.residual_tolerance = 1e-13;
  NewtonOptions chord = newton_only;
  chord.chord_rate = 0.25;
  Vector u_newton = problem.initial_guess(), u_chord = problem.initial_guess();
  NewtonSolver a(problem, newton_only), b(problem, chord);
  const NewtonResult ra = a.solve(u_newton), rb = b.solve(u_chord);
  ASSERT_TRUE(ra.converged()) << ra.status.describe();
  ASSERT_TRUE(rb.converged()) << rb.status.describe();
  std::cout << "Newton: " << ra.iterations << " iterations, " << ra.factorisations
            << " factorisations; chord_rate 0.25: " << rb.iterations << " iterations, " << rb.factorisations
            << " factorisations\n";
  EXPECT_EQ(ra.factorisations, ra.iterations);
  EXPECT_LT(rb.factorisations, ra.factorisations);
  EXPECT_LE(rb.residual_norm, 1e-13);
  EXPECT_LT((u_chord - u_newton).cwiseAbs().maxCoeff(), 1e-10);
  // an iteration that did not cut |F| by the rate (chord or not) is followed by a new Jacobian
  int chords = 0;
  for (size_t k = 0; k + 1 < rb.history.size(); ++k) {
    chords += rb.history[k].chord;
    if (!(rb.history[k + 1].residual_norm <= 0.25 * rb.history[k].residual_norm) || rb.history[k].step_length < 1) {
      EXPECT_FALSE(rb.history[k + 1].chord) << "iteration " << k + 1;
    }
  }
  EXPECT_GE(chords, 2);
}

// With chord_rate a tolerance below the rounding floor ends on the chord: a chord iteration that
// stops falling within 1e3 of the tolerance is the floor, not a reason for a new Jacobian.
TEST(Newton, ChordStopsAtTheRoundingFloorWithoutANewJacobian) {
  Bratu1DProblem problem(64, 2.0);  // floor about 3e-13
  const Vector ref = solved_to_reachable_tolerance(problem);
  NewtonOptions below = below_the_floor();
  below.chord_rate = 0.25;
  NewtonSolver newton(problem, below);
  Vector u = problem.initial_guess();
  const NewtonResult res = newton.solve(u);
  ASSERT_TRUE(res.converged()) << res.status.describe();
  std::cout << res.iterations << " iterations, " << res.factorisations << " factorisations, |F| = " << res.residual_norm
            << "\n";
  EXPECT_LE(res.residual_norm, 1e-12);
  EXPECT_LT((u - ref).cwiseAbs().maxCoeff(), 1e-10);
  ASSERT_FALSE(res.history.empty());
  EXPECT_TRUE(res.history.back().chord);  // the last iteration solved on a kept factorisation
  EXPECT_LT(res.factorisations, res.iterations);
}

// Below the problem's rounding floor (eps max_i sum_j |J_ij| |u_j|, ConvergenceTest) a chord that
// falls slower than chord_rate is rounding, not an old matrix: it goes on without a new Jacobian.
// The problem: F = (1e3 (u1 - 1), 1e7 (u2 - 1)) with u2 at its root exactly, so the second row's
// 1e7 sets an estimated floor of 2.2e-9 that the first row's own rounding (1e-13) lies far below;
// the Jacobian reported is 1/0.6 of the true one, so every iteration, on its own Jacobian or a
// kept one, cuts |F| by 0.4 exactly, slower than the rate 0.25. Above the floor each iteration
// renews; below it, none does (each renewed while the floor was not passed to the renewal policy,
// which made a factorisation of every step of the shooting map's forward runs).
TEST(Newton, ASlowChordBelowTheRoundingFloorKeepsItsFactorisation) {
  test::FunctionProblem problem(
      "floored", 2, {},
      [](const Vector& u, const Vector&) {
        Vector F(2);
        F << 1e3 * (u[0] - 1.0), 1e7 * (u[1] - 1.0);
        return F;
      },
      [](const Vector&, const Vector&) {
        Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2, 2);
        J(0, 0) = 1e3 / 0.6;
        J(1, 1) = 1e7;
        return J;
      },
      nullptr);
  Vector u(2);
  u << 1.0 - 1e-8, 1.0;
  Vector F;
  SparseMatrix J;
  ASSERT_TRUE(problem.jacobian(u, F, J).is_ok());
  const double floor = rounding_floor(J, u);
  ASSERT_NEAR(floor, 1e7 * std::numeric_limits<double>::epsilon(), 1e-3 * floor);
  NewtonOptions o;
  o.residual_tolerance = 1e-18;  // below the floor
  o.update_tolerance = 0.0;
  o.chord_rate = 0.25;
  o.line_search = false;
  o.max_iterations = 40;
  NewtonSolver newton(problem, o);
  const NewtonResult r = newton.solve(u);
  ASSERT_TRUE(r.converged()) << r.status.describe();
  EXPECT_LE(r.residual_norm, 1e-12);
  EXPECT_LT(std::abs(u[0] - 1.0), 1e-14);
  int above = 0, below = 0;
  for (size_t k = 1; k < r.history.size(); ++k) {
    const NewtonIteration& it = r.history[k];
    if (it.residual_norm > floor) {  // the residual the renewal was decided on
      ++above;
      EXPECT_FALSE(it.chord) << "iteration " << it.iteration << " after a fall of 0.4 above the floor";
    } else {
      ++below;
      EXPECT_TRUE(it.chord) << "iteration " << it.iteration << " at |F| = " << it.residual_norm << " below the floor "
                            << floor;
    }
  }
  EXPECT_GE(above, 5);  // 1e-5 to 2.2e-9 at 0.4 an iteration
  EXPECT_GE(below, 5);  // 2.2e-9 to the first row's rounding, about 1e-13
  EXPECT_EQ(r.factorisations, above + 1);
}

// With chord_rate a reachable tolerance is reached: a chord that slows down within 1e3 of the
// tolerance gets a new Jacobian, it is not taken for the rounding floor (which stalls). u^3 - 3u
// = lambda from u = -2, to tolerances between 1e-3 and 1e-8: every solve ends at or below its
// tolerance.
TEST(Newton, ChordReachesAReachableTolerance) {
  for (const double lambda : {-50.0, -20.0, -5.0, 10.0, 30.0})
    for (const double tol : {1e-3, 1e-4, 2e-4, 1e-6, 1e-8}) {
      test::CubicProblem problem(lambda);
      NewtonOptions o;
      o.residual_tolerance = tol;
      o.update_tolerance = 0.0;
      o.chord_rate = 0.25;
      NewtonSolver newton(problem, o);
      Vector u = problem.initial_guess();
      const NewtonResult res = newton.solve(u);
      ASSERT_TRUE(res.converged()) << "lambda " << lambda << ", tolerance " << tol << ": " << res.status.describe();
      EXPECT_LE(res.residual_norm, tol * problem.residual_scale()) << "lambda " << lambda << ", tolerance " << tol;
    }
}

// A chord iteration solves without iterative refinement (its error is the kept matrix's age); an
// iteration on its own Jacobian with the LU options' refinement. The chord runs above converge to
// the Newton-only solution with it (ChordRateSavesFactorisationsInTheFinalPhase: to 1e-10).
TEST(Newton, OnlyAnIterationOnItsOwnJacobianRefinesItsSolve) {
  EXPECT_EQ(NewtonSolver::refinement_steps(true), 0);
  EXPECT_EQ(NewtonSolver::refinement_steps(false), -1);  // SparseLU::solve's "the options'"
}
