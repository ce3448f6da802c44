#include "core/Newton.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "core/ConvergenceTest.hpp"
#include "core/RenewalPolicy.hpp"

namespace keller {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
double inf_norm(const Vector& v) { return v.size() ? v.lpNorm<Eigen::Infinity>() : 0.0; }
}  // namespace

NewtonSolver::NewtonSolver(Problem& problem, NewtonOptions options, SparseLUOptions lu_options)
    : problem_(problem),
      options_(options),
      lu_(std::make_shared<SparseLU>(lu_options)),
      J_(problem.jacobian_pattern()) {}

NewtonResult NewtonSolver::solve(Vector& u, const Observer& observer, bool on_kept) {
  NewtonResult res;
  const auto t_start = Clock::now();
  ConvergenceTest test;
  test.tolerance = options_.residual_tolerance * problem_.residual_scale();
  test.update_tolerance = options_.update_tolerance;
  RenewalPolicy renewal;
  renewal.chord_rate = options_.chord_rate;
  renewal.max_iterations = options_.max_iterations;
  Vector F, du, F_try, u_try;
  Status st = problem_.residual(u, F);
  if (!st.is_ok()) {
    res.status = {st.code(), "initial residual: " + st.message()};
    return res;
  }
  const double F0 = inf_norm(F);
  double normF = F0;           // convergence is judged in the max norm
  double norm2 = F.norm();     // the line search in the 2-norm, for which du is a descent direction
  double previous = INFINITY;  // |F| one iteration before normF
  double best = F0;            // the smallest |F| so far
  double contraction = 0.0;    // the fall of the last iteration, the chord's rate on a kept factorisation
  int on_this_matrix = 0;      // iterations made with the present factorisation
  // the next iteration solves with the last factorisation (RenewalPolicy)
  bool reuse = on_kept && lu_->factorized();
  // Below the problem's own rounding floor a chord that falls slower than its rate is rounding, not
  // an old matrix: no new Jacobian for it (the convergence test stops it once it stalls). A
  // tolerance under the floor (the shooting map's forward steps: 1e-13 of the residual scale on the
  // collapsible channel, whose floor is 60 times that) made a factorisation of every step there.
  // Not the floor level's band of 1e3 tolerances: there a reachable tolerance's slow chord renews.
  if (reuse) test.problem_floor = renewal.floor_level = floor_;
  for (int k = 0;; ++k) {
    if (normF <= test.tolerance) break;
    if (k >= options_.max_iterations) {
      res.status = {
          StatusCode::NotConverged,
          fmt::format("no convergence in {} iterations (|F| = {:.3e}, tolerance {:.3e})", k, normF, test.tolerance)};
      break;
    }
    NewtonIteration it;
    it.iteration = k + 1;
    it.residual_norm = normF;
    const auto t_it = Clock::now();

    it.chord = reuse;
    auto t0 = Clock::now();
    if (!reuse) {
      st = problem_.jacobian(u, F, J_);
      it.assembly_seconds = since(t0);
      if (!st.is_ok()) {
        res.status = {st.code(), "Jacobian: " + st.message()};
        break;
      }
      floor_ = rounding_floor(J_, u);
      test.problem_floor = renewal.floor_level = floor_;
      t0 = Clock::now();
      st = lu_->factorize(J_);
      it.factor_seconds = since(t0);
      if (!st.is_ok()) {
        res.status = st;
        break;
      }
      J_at_ = u;
      ++res.factorisations;
      on_this_matrix = 0;
    }
    t0 = Clock::now();
    st = lu_->solve(-F, du, false, refinement_steps(reuse));
    it.solve_seconds = since(t0);
    if (!st.is_ok()) {
      res.status = st;
      break;
    }
    ++on_this_matrix;
    it.update_norm = inf_norm(du);

    t0 = Clock::now();
    double alpha = 1.0;
    bool accepted = false;
    double norm_try = 0, norm2_try = 0;
    Status last;
    while (alpha >= options_.min_step_length) {
      u_try = u + alpha * du;
      last = problem_.residual(u_try, F_try);
      if (last.is_ok()) {
        norm_try = inf_norm(F_try);
        norm2_try = F_try.norm();
        if (!options_.line_search || norm_try <= test.tolerance || norm2_try < (1.0 - 1e-4 * alpha) * norm2) {
          accepted = true;
          break;
        }
        // a full step at rounding level cannot reduce |F| further: accept it
        if (alpha == 1.0 && it.update_norm <= options_.update_tolerance * std::max(inf_norm(u), 1.0)) {
          accepted = true;
          break;
        }
      }
      alpha *= 0.5;
    }
    it.line_search_seconds = since(t0);
    it.step_length = alpha;
    it.seconds = since(t_it);
    res.assembly_seconds += it.assembly_seconds;
    res.factor_seconds += it.factor_seconds;
    res.solve_seconds += it.solve_seconds;
    res.line_search_seconds += it.line_search_seconds;
    res.history.push_back(it);
    res.iterations = k + 1;
    if (observer) observer(it);
    if (!accepted && it.chord) {
      // the old matrix's direction: the next iteration from the same iterate with a new one
      // (only a fresh Jacobian's failure says rounding floor, below)
      reuse = false;
      continue;
    }
    if (!accepted && last.is_ok() && normF <= test.floor_level()) {
      // no step reduces a residual already at the rounding floor
      res.at_rounding_floor = true;
      break;
    }
    if (!accepted) {
      res.status = last.is_ok() ? Status{StatusCode::Diverged,
                                         fmt::format("line search failed: no step length >= {} reduces |F| = {:.3e}",
                                                     options_.min_step_length, normF)}
                                : Status{last.code(), "every damped step failed: " + last.message()};
      break;
    }
    u.swap(u_try);
    F.swap(F_try);
    const double before_previous = previous;
    previous = normF;
    normF = norm_try;
    norm2 = norm2_try;
    ConvergenceTest::Iterate now;
    now.residual = normF;
    now.previous = previous;
    now.before_previous = before_previous;
    best = std::min(best, normF);
    now.best = best;
    now.update = alpha == 1.0 ? it.update_norm : INFINITY;
    now.contraction = it.chord ? contraction : 0.0;
    now.scale = std::max(inf_norm(u), 1.0);
    const ConvergenceTest::Verdict verdict = test.judge(now);
    contraction = normF / previous;
    if (verdict != ConvergenceTest::Verdict::Continue) {
      res.at_rounding_floor = verdict == ConvergenceTest::Verdict::RoundingFloor;
      break;
    }
    if (normF > options_.divergence_factor * std::max(F0, test.tolerance)) {
      res.status = {StatusCode::Diverged, fmt::format("|F| grew to {:.3e} from {:.3e}", normF, F0)};
      break;
    }
    RenewalPolicy::History h;
    h.iteration = k + 1;
    h.on_this_matrix = on_this_matrix;
    h.residual = normF;
    h.previous = previous;
    h.before_previous = before_previous;
    h.goal = test.tolerance;
    h.full_step = alpha == 1.0;
    reuse = !renewal.renew(h);
  }
  res.residual_norm = normF;
  res.seconds = since(t_start);
  return res;
}

void declare_newton_keys(SceneSchema& s) {
  s.section("newton", "Newton iteration for each steady state");
  s.integer("newton.max_iterations", 20, "iterations (chord ones included) before giving up", Range::at_least(1));
  s.real("newton.residual_tolerance", 1e-10,
         "converged when max |F| <= this times the problem's residual scale (Gamma for channel flows)",
         Range::positive());
  s.real("newton.update_tolerance", 1e-12, "or when a full step has max |du| <= this times max(|u|, 1)",
         Range::positive());
  s.boolean("newton.line_search", true, "halve the step until |F| decreases");
  s.real("newton.min_step_length", 1.0 / 128.0, "smallest step length of the line search", Range::between(1e-8, 1.0));
  s.real("newton.chord_rate", 0.25,
         "once a full step cuts max |F| by this factor, keep its factorisation while each iteration does (the "
         "final phase contracts fast and a factorisation costs tens of solves); 0: a new Jacobian every iteration",
         Range{0.0, 1.0, false, true});
}

NewtonOptions newton_options_from(const Scene& scene) {
  NewtonOptions o;
  o.max_iterations = static_cast<int>(scene.integer("newton.max_iterations"));
  o.residual_tolerance = scene.real("newton.residual_tolerance");
  o.update_tolerance = scene.real("newton.update_tolerance");
  o.line_search = scene.boolean("newton.line_search");
  o.min_step_length = scene.real("newton.min_step_length");
  o.chord_rate = scene.real("newton.chord_rate");
  return o;
}

void print_newton_header() {
  fmt::print("  {:>4}  {:>12}  {:>12}  {:>6}  {:>9}  {:>9}  {:>9}\n", "iter", "|F|", "|du|", "step", "assemble",
             "factor", "total s");
}

void print_newton_row(const NewtonIteration& it) {
  fmt::print("  {:>4}  {:>12.4e}  {:>12.4e}  {:>6.3f}  {:>9.4f}  {:>9.4f}  {:>9.4f}\n", it.iteration, it.residual_norm,
             it.update_norm, it.step_length, it.assembly_seconds, it.factor_seconds, it.seconds);
  std::fflush(stdout);
}

}  // namespace keller
