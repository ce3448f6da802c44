#include "core/Newton.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

namespace keller {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
double inf_norm(const Vector& v) { return v.size() ? v.lpNorm<Eigen::Infinity>() : 0.0; }
}  // namespace

NewtonSolver::NewtonSolver(Problem& problem, NewtonOptions options, SparseLUOptions lu_options)
    : problem_(problem), options_(options), lu_(lu_options), J_(problem.jacobian_pattern()) {}

NewtonResult NewtonSolver::solve(Vector& u, const Observer& observer) {
  NewtonResult res;
  const auto t_start = Clock::now();
  const double tol_F = options_.residual_tolerance * problem_.residual_scale();
  Vector F, du, F_try, u_try;
  Status st = problem_.residual(u, F);
  if (!st.is_ok()) {
    res.status = {st.code(), "initial residual: " + st.message()};
    return res;
  }
  const double F0 = inf_norm(F);
  double normF = F0;        // convergence is judged in the max norm
  double norm2 = F.norm();  // the line search in the 2-norm, for which du is a descent direction
  // chord_rate: the last step was full and cut |F| by the rate (its matrix is then good enough
  // for the next one)
  bool reuse = false;
  for (int k = 0;; ++k) {
    if (normF <= tol_F) break;
    if (k >= options_.max_iterations) {
      res.status = {StatusCode::NotConverged,
                    fmt::format("no convergence in {} iterations (|F| = {:.3e}, tolerance {:.3e})", k, normF, tol_F)};
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
      t0 = Clock::now();
      st = lu_.factorize(J_);
      it.factor_seconds = since(t0);
      if (!st.is_ok()) {
        res.status = st;
        break;
      }
      ++res.factorisations;
    }
    t0 = Clock::now();
    st = lu_.solve(-F, du);
    it.solve_seconds = since(t0);
    if (!st.is_ok()) {
      res.status = st;
      break;
    }
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
        if (!options_.line_search || norm_try <= tol_F || norm2_try < (1.0 - 1e-4 * alpha) * norm2) {
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
    if (!accepted && last.is_ok() && normF <= 1e3 * tol_F) {
      // no step reduces a residual already within 1e3 of the tolerance: the rounding floor of
      // this problem (large coupled systems sit at 1e-13 while the tolerance asks 5e-15)
      res.residual_norm = normF;
      break;
    }
    if (!accepted) {
      res.status = last.is_ok() ? Status{StatusCode::Diverged,
                                         fmt::format("line search failed: no step length >= {} reduces |F| = {:.3e}",
                                                     options_.min_step_length, normF)}
                                : Status{last.code(), "every damped step failed: " + last.message()};
      break;
    }
    const bool fell = alpha == 1.0 && norm_try <= options_.chord_rate * normF;
    // a chord that had been cutting |F| by the rate and now stalls (under 10%) within 1e3 of the
    // tolerance has reached the rounding floor: converged (a new Jacobian would not lower |F|
    // there). A chord that merely slows down gets a new Jacobian next.
    // So has, with chord_rate, a step on a new Jacobian that cuts |F| by less than the rate
    // there (or only damped): so close to the solution Newton cuts it by orders of magnitude.
    const bool stalled = norm_try <= 1e3 * tol_F &&
                         ((it.chord && norm_try > 0.9 * normF) || (!it.chord && options_.chord_rate > 0 && !fell));
    reuse = options_.chord_rate > 0 && fell;
    u.swap(u_try);
    F.swap(F_try);
    normF = norm_try;
    norm2 = norm2_try;
    if (stalled) break;
    if (normF > options_.divergence_factor * std::max(F0, tol_F)) {
      res.status = {StatusCode::Diverged, fmt::format("|F| grew to {:.3e} from {:.3e}", normF, F0)};
      break;
    }
    if (alpha == 1.0 && it.update_norm <= options_.update_tolerance * std::max(inf_norm(u), 1.0)) break;
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
  s.real("newton.chord_rate", 0.0,
         "0: a new Jacobian every iteration; else, once a full step cuts max |F| by this factor, keep its "
         "factorisation while each iteration does",
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
