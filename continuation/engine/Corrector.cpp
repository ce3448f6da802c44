#include "continuation/engine/Corrector.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>

#include "core/Anderson.hpp"
#include "core/ConvergenceTest.hpp"
#include "core/RenewalPolicy.hpp"

namespace keller {

namespace {
// A residual that grows by this factor in one iteration is diverging (a step far off the branch).
constexpr double kDivergenceFactor = 1e3;
// The neighbours' floor is raised by this factor for a located point between them (rounding
// wanders from one point to the next).
constexpr double kNeighbourFloorMargin = 2.0;
}  // namespace

Corrector::Corrector(Evaluator& ev, KeptFactorisation& kept, const ArclengthNorm& norm,
                     const ContinuationOptions& options, const NewtonOptions& newton)
    : ev_(ev), kept_(kept), norm_(norm), options_(options), newton_(newton) {}

double Corrector::tolerance() const { return newton_.residual_tolerance * ev_.problem().residual_scale(); }

double Corrector::residual_floor(double r0, double r1) const {
  const double r = std::max(r0, r1);
  return r > tolerance() ? kNeighbourFloorMargin * r : 0.0;
}

double Corrector::renewal_cost() const {
  return options_.corrector.renewal_cost ? *options_.corrector.renewal_cost
                                         : kept_.measured_renewal_cost(ev_.timings());
}

CorrectorResult Corrector::correct(Vector& u, double& lambda, const Constraint& c, Kind kind, double floor) {
  const bool kept_chord = kind == Kind::Located && options_.corrector.kept();
  Vector u0;
  if (kept_chord) u0 = u;
  const double lambda0 = lambda;
  CorrectorResult r = iterate(u, lambda, c, kind, floor);
  if (!r.status.is_ok() && kept_chord && !r.refactored) {
    // a located point's chord that failed on the kept factorisation (its rate worsened): once
    // more from the same prediction with a factorisation made there
    u = std::move(u0);
    lambda = lambda0;
    kept_.record(ReuseEvent::Diverged);
    const int first = r.iterations;
    r = iterate(u, lambda, c, kind, floor);
    r.iterations += first;
  }
  kept_.record(r.status.is_ok() ? ReuseEvent::Converged : ReuseEvent::Diverged);
  return r;
}

CorrectorResult Corrector::iterate(Vector& u, double& lambda, const Constraint& c, Kind kind, double floor) {
  CorrectorResult r;
  const CorrectorOptions& co = options_.corrector;
  const bool chord = co.method == CorrectorOptions::Method::Chord;
  const int max_iterations = options_.max_iterations();
  // A located point's chord on a kept factorisation aims at the tolerance or, where that lies
  // below rounding, at the floor its neighbours reached; so does a step's chord on a kept
  // factorisation, which goes on slowly where that is cheaper than a renewal (renewal_cost), at
  // the floor the last two points reached.
  const bool located_kept = kind == Kind::Located && co.kept();
  const double cost = kind == Kind::Step && co.kept() ? renewal_cost() : 0.0;
  const bool costed_step = cost > 0;
  const bool slow = located_kept || costed_step;

  ConvergenceTest test;
  test.tolerance = tolerance();
  test.update_tolerance = newton_.update_tolerance;
  test.problem_floor = ev_.rounding_floor();
  test.slow = slow;
  if (slow) test.aim_at_floor(floor);

  RenewalPolicy renewal;
  renewal.chord_rate = co.chord_rate;
  renewal.max_iterations = max_iterations;
  renewal.reach_goal = located_kept;
  renewal.renewal_cost = cost;
  // near the rounding floor a slower fall is rounding, not an old matrix (where the chord may not
  // go on slowly; the convergence test then stops it)
  if (chord && !slow) renewal.floor_level = test.floor_level();

  double previous = INFINITY, before_previous = INFINITY, update = INFINITY, best = INFINITY;
  std::optional<std::tuple<Vector, double, double>> on_branch;  // a prediction already there: u, lambda, |F|
  const auto back_on_branch = [&]() {
    auto& [u0, l0, r0] = *on_branch;
    u = std::move(u0);
    lambda = l0;
    r.residual = r0;
    r.status = ev_.set_parameter(lambda);  // (the evaluator's parameter back at the point's)
    return r;
  };
  int on_this_matrix = 0;  // iterations made with the present factorisation
  double dl = 0;
  AndersonMixer mixer(chord ? co.anderson_depth : 0);
  bool newton_iteration = false;   // the last iteration was made on a Jacobian of its own iterate
  double newton_correction = 0.0;  // the length of its correction
  for (int k = 0;; ++k) {
    Status st = ev_.set_parameter(lambda);
    if (st.is_ok()) st = ev_.residual(u, F_);
    if (!st.is_ok()) {
      r.status = st;
      return r;
    }
    const double normF = F_.lpNorm<Eigen::Infinity>();
    r.residual = normF;
    best = std::min(best, normF);
    // A located point's prediction (the cubic through two converged neighbours) may already be on
    // the branch. It is iterated all the same (the tangent and the determinant's sign there use the
    // factorisation made on the way), but where the iteration moves away from it instead (next to a
    // branch point, where J is nearly singular, rounding grows along its null vector), or fails,
    // the prediction is the point.
    if (k == 0 && kind == Kind::Located && normF <= test.aim()) {
      on_branch.emplace(u, lambda, normF);
    } else if (on_branch && (normF > kFloorWander * std::get<2>(*on_branch) || !std::isfinite(normF))) {
      return back_on_branch();
    }
    if (k > 0) {
      ConvergenceTest::Iterate now;
      now.residual = normF;
      now.previous = previous;
      now.before_previous = before_previous;
      now.best = best;
      now.update = update;
      now.contraction = newton_iteration ? 0.0 : std::min(normF / previous, 1.0);
      now.scale = std::max(u.lpNorm<Eigen::Infinity>(), 1.0);
      test.problem_floor = ev_.rounding_floor();
      const ConvergenceTest::Verdict verdict = test.judge(now);
      if (verdict != ConvergenceTest::Verdict::Continue) {
        r.at_rounding_floor = verdict == ConvergenceTest::Verdict::RoundingFloor;
        return r;
      }
      if (normF > kDivergenceFactor * previous) {
        r.status = {StatusCode::Diverged, fmt::format("corrector diverged (|F| = {:.3e})", normF)};
        return on_branch ? back_on_branch() : r;
      }
    }
    if (k >= max_iterations) {
      r.status = {StatusCode::NotConverged,
                  fmt::format("corrector did not converge in {} iterations (|F| = {:.3e})", k, normF)};
      return on_branch ? back_on_branch() : r;
    }
    bool refactor = !chord || k == 0;
    if (chord && k > 0) {
      RenewalPolicy::History h;
      h.iteration = k;
      h.on_this_matrix = on_this_matrix;
      h.residual = normF;
      h.previous = previous;
      h.before_previous = before_previous;
      h.goal = test.aim();
      refactor = renewal.renew(h);
    }
    // the first iteration of a chord starts on the kept factorisation, under this step's row
    if (k == 0 && chord && co.kept() && kept_.reusable()) refactor = !kept_.set_row(c).is_ok();
    before_previous = previous;
    previous = normF;
    const double N = c.value(u, lambda);
    // Deuflhard's monotonicity test for a step: after an iteration on a Jacobian made at its own
    // iterate (a Newton iteration), the simplified Newton correction -J^-1 F on that same
    // factorisation must be shorter than the Newton correction, or the step started outside
    // Newton's region of contraction and a shorter one is cheaper than more Jacobians. In the
    // arclength norm of the corrections, not in |F|, whose rows scale unevenly. Where the
    // factorisation is kept, the simplified correction is this iteration's update: no extra solve.
    bool have_update = false;
    if (kind == Kind::Step && chord && newton_iteration && newton_correction > 0) {
      st = kept_.solve(-F_, -N, du_, dl, false);
      if (!st.is_ok()) {
        r.status = st;
        return r;
      }
      const double theta = norm_.norm(du_, dl) / newton_correction;
      if (!(theta < 1.0)) {
        r.status = {StatusCode::Diverged,
                    fmt::format("corrector: the simplified Newton correction is {:.3g} times the Newton correction "
                                "(monotonicity test)",
                                theta)};
        return r;
      }
      have_update = !refactor;
    }
    newton_iteration = refactor;
    if (refactor) {
      r.refactored = true;
      st = ev_.jacobian(u);
      if (st.is_ok()) st = ev_.parameter_derivative(u);
      if (st.is_ok()) st = kept_.factorise_assembled(ev_, u, lambda, c);
      if (!st.is_ok()) {
        r.status = st;
        return r;
      }
      on_this_matrix = 0;
      mixer.reset();
    }
    ++on_this_matrix;
    // the chord corrects the error of an unrefined solve like that of its old matrix
    if (!have_update) st = kept_.solve(-F_, -N, du_, dl, !chord);
    if (!st.is_ok()) {
      r.status = st;
      return r;
    }
    if (refactor) newton_correction = norm_.norm(du_, dl);
    // (the unaccelerated update: the accelerated one may be small where the chord is not)
    update = std::max(du_.lpNorm<Eigen::Infinity>(), std::abs(dl));
    mixer.mix(u, lambda, du_, dl);
    u += du_;
    lambda += dl;
    ++r.iterations;
    if (!u.allFinite() || !std::isfinite(lambda)) {
      r.status = {StatusCode::NotFinite, "corrector produced a non-finite state"};
      return on_branch ? back_on_branch() : r;
    }
  }
}

}  // namespace keller
