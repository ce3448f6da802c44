#include "continuation/Continuation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <stdexcept>

#include "continuation/Hermite.hpp"
#include "core/Anderson.hpp"

namespace keller {

const char* to_string(PointKind k) {
  switch (k) {
    case PointKind::Regular: return "point";
    case PointKind::Start: return "start";
    case PointKind::Requested: return "requested";
    case PointKind::Event: return "event";
    case PointKind::Fold: return "fold";
    case PointKind::BranchPoint: return "branch-point";
    case PointKind::End: return "end";
    case PointKind::Hopf: return "hopf";
  }
  return "?";
}

const char* to_string(StopCode c) {
  switch (c) {
    case StopCode::UpperBound: return "upper-bound";
    case StopCode::LowerBound: return "lower-bound";
    case StopCode::StopObservable: return "stop-observable";
    case StopCode::MaxSteps: return "max-steps";
    case StopCode::StepFloor: return "step-floor";
    case StopCode::Interrupted: return "interrupted";
  }
  return "?";
}

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
int sign_of(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }
}  // namespace

Continuation::Continuation(Problem& problem, ContinuationOptions options, NewtonOptions newton, SparseLUOptions lu)
    : problem_(problem), options_(std::move(options)), newton_(newton), lu_options_(lu) {
  options_.validate();
  p_ = problem_.parameters().index(options_.parameter);
  if (!options_.stop_observable.empty()) {
    const auto names = problem_.observable_names();
    auto it = std::find(names.begin(), names.end(), options_.stop_observable);
    if (it == names.end()) {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown observable '" + options_.stop_observable + "'; this problem has: " + known);
    }
    stop_index_ = static_cast<int>(it - names.begin());
  }
  monitor_names_ = problem_.monitor_names();
  if (stop_index_ >= 0) {
    if (std::isfinite(options_.stop_above)) monitor_names_.push_back(options_.stop_observable + " > stop_above");
    if (std::isfinite(options_.stop_below)) monitor_names_.push_back(options_.stop_observable + " < stop_below");
  }
  bordered_ = std::make_unique<BorderedSystem>(
      problem_.jacobian_pattern(), lu,
      options_.block_elimination ? BorderedSystem::Mode::Block : BorderedSystem::Mode::Full);
  J_ = problem_.jacobian_pattern();
}

double Continuation::dot(const Vector& u1, double l1, const Vector& u2, double l2) const {
  return wu_ * u1.dot(u2) + wl_ * l1 * l2;
}

Status Continuation::set_parameter(double lambda) {
  ParameterSet& ps = problem_.parameters();
  if (!std::isfinite(lambda)) return {StatusCode::NotFinite, "parameter is not finite"};
  if (!ps.admissible(p_, lambda))
    return {StatusCode::InvalidState, fmt::format("{} = {} is outside its admissible range [{}, {}]", options_.parameter,
                                                  lambda, ps.info(p_).lower, ps.info(p_).upper)};
  ps.set(p_, lambda);
  return {};
}

Continuation::Constraint Continuation::arclength_constraint(const BranchPoint& from, const Vector& tu, double tl,
                                                            double sigma) const {
  Constraint c;
  c.cu = wu_ * tu;
  c.cl = wl_ * tl;
  c.u0 = &from.u;
  c.l0 = from.lambda;
  c.target = sigma;
  return c;
}

std::optional<Continuation::Landing> Continuation::landing(const BranchPoint& cur, const BranchPoint* prev, double ds,
                                                          double dl_dir) const {
  // (after a landing that failed, the step's retries are ordinary steps: the value is located
  // after them, or reported as not located, instead of failing again at the same place)
  if (!options_.land_on_values || options_.method != ContinuationOptions::Method::Arclength || landing_failed_)
    return std::nullopt;
  if (!(std::abs(dl_dir) > 0)) return std::nullopt;
  // Near a fold the correction at a fixed parameter value is ill-posed and the value may lie
  // beyond the fold: a step lands only within half the distance at which the parameter part of
  // the tangent, extrapolated linearly from the last two points, vanishes (and not right after
  // a fold). In units of the branch itself, whatever the scale of the parameter.
  double to_fold = std::numeric_limits<double>::infinity();
  if (prev && prev->tu.size() && cur.s > prev->s) {
    if (prev->tlambda * cur.tlambda <= 0) return std::nullopt;
    const double slope = (cur.tlambda - prev->tlambda) / (cur.s - prev->s);
    if (slope * cur.tlambda < 0) to_fold = -cur.tlambda / slope;
  }
  const double predicted = cur.lambda + ds * dl_dir;
  std::optional<Landing> best;
  // sense: +1 only crossing upwards (the upper bound, left from inside), -1 only downwards (the
  // lower bound), 0 either way (stops)
  auto consider = [&](double v, int sense, PointKind kind, std::string label, bool terminal, StopCode code) {
    if (!std::isfinite(v) || v == cur.lambda || !((cur.lambda - v) * (predicted - v) <= 0)) return;
    if (sense * (v - cur.lambda) < 0) return;
    const double fraction = (v - cur.lambda) / (predicted - cur.lambda);
    if (fraction * ds > 0.5 * to_fold) return;
    if (!best || fraction < best->fraction) best = Landing{v, fraction, kind, std::move(label), terminal, code};
  };
  consider(options_.upper, +1, PointKind::End, "upper", true, StopCode::UpperBound);
  consider(options_.lower, -1, PointKind::End, "lower", true, StopCode::LowerBound);
  for (double v : options_.stops)
    consider(v, 0, PointKind::Requested, fmt::format("{} = {}", options_.parameter, v), false, StopCode::MaxSteps);
  return best;
}

double Continuation::residual_floor(double r0, double r1) const {
  // neighbours that reached the tolerance say nothing of rounding: no floor then
  const double r = std::max(r0, r1);
  return r > newton_.residual_tolerance * problem_.residual_scale() ? 2.0 * r : 0.0;
}

Continuation::Constraint Continuation::lambda_constraint(double lambda) const {
  Constraint c;
  c.cl = 1.0;
  c.l0 = 0.0;
  c.target = lambda;
  return c;
}

Status Continuation::correct(Vector& u, double& lambda, const Constraint& c, int& iterations, bool step) {
  const bool kept_chord = located_on_kept_factorisation(step);
  Vector u0;
  if (kept_chord) u0 = u;
  const double lambda0 = lambda;
  Status st = correct_iterations(u, lambda, c, iterations, step);
  if (!st.is_ok() && kept_chord && !refactored_) {
    // a located point's chord that failed on the kept factorisation (its rate worsened): once
    // more from the same prediction with a factorisation made there
    u = std::move(u0);
    lambda = lambda0;
    reusable_ = false;
    int more = 0;
    st = correct_iterations(u, lambda, c, more, step);
    iterations += more;
  }
  // a factorisation made at a diverging iterate is not kept for the next attempt
  reusable_ = st.is_ok();
  return st;
}

Status Continuation::correct_iterations(Vector& u, double& lambda, const Constraint& c, int& iterations, bool step) {
  iterations = 0;
  refactored_ = false;
  const double tol = newton_.residual_tolerance * problem_.residual_scale();
  double previous = INFINITY, before_previous = INFINITY, update = INFINITY;
  int on_this_matrix = 0;  // iterations made with the present factorisation
  const bool chord = options_.corrector == ContinuationOptions::Corrector::Chord;
  // a located point's chord on a kept factorisation aims at the tolerance or, where that lies
  // below rounding, at the floor its neighbours reached (within 1e3 of the tolerance)
  const bool located_kept = located_on_kept_factorisation(step);
  // so does a step's chord on a kept factorisation that may go on slowly (renewal_cost), at the
  // floor the last two points reached
  const bool costed_step = step && chord && options_.reuse_factorisation && options_.renewal_cost > 0;
  const bool slow_chord_allowed = located_kept || costed_step;
  const double floor = located_kept ? located_floor_ : step_floor_;
  const double goal = slow_chord_allowed ? std::max(tol, std::min(floor, 1e3 * tol)) : tol;
  Vector du;
  double dl = 0;
  // the chord's iterates on one factorisation, accelerated (anderson_depth > 0)
  AndersonMixer mixer(chord ? options_.anderson_depth : 0);
  bool newton_iteration = false;  // the last iteration was made on a Jacobian of its own iterate
  double newton_correction = 0.0;  // the length of its correction
  for (int k = 0;; ++k) {
    Status st = set_parameter(lambda);
    if (!st.is_ok()) return st;
    const auto t_res = std::chrono::steady_clock::now();
    st = problem_.residual(u, F_);
    timings_.residual += seconds_since(t_res);
    ++timings_.residuals;
    if (!st.is_ok()) return st;
    const double normF = F_.lpNorm<Eigen::Infinity>();
    if (k > 0) {
      const bool small_update = update <= newton_.update_tolerance * std::max(u.lpNorm<Eigen::Infinity>(), 1.0);
      // the rounding floor: within 1e3 of the tolerance and no longer falling (as in Newton). A
      // located point's chord on a kept factorisation may fall slowly but steadily (see below):
      // there the fall over two iterations must stall too (under 10%), or a slow chord passes
      // for rounding; a chord slower than the tolerance allows is renewed instead (below)
      const bool stalled =
          normF > 0.5 * previous && (!slow_chord_allowed || (k >= 2 && normF > 0.9 * before_previous));
      if (normF <= goal || ((small_update || stalled) && normF <= 1e3 * tol)) {
        last_residual_ = normF;
        return {};
      }
      if (normF > 1e3 * previous) return {StatusCode::Diverged, fmt::format("corrector diverged (|F| = {:.3e})", normF)};
    }
    if (k >= options_.max_iterations)
      return {StatusCode::NotConverged,
              fmt::format("corrector did not converge in {} iterations (|F| = {:.3e})", k, normF)};
    // chord: keep the factorisation while |F| falls fast enough (with reuse_factorisation also
    // the one of the previous step, under this step's border row)
    bool refactor = !chord || k == 0 || !(normF <= options_.chord_rate * previous);
    // the iterations this matrix's chord still needs to reach the goal at its observed rate (the
    // mean of its last two, which wander)
    auto more_at_its_rate = [&]() {
      const double rate = on_this_matrix >= 2 ? std::sqrt(normF / before_previous) : normF / previous;
      return rate < 1.0 ? std::max(0.0, std::log(goal / normF) / std::log(rate)) : INFINITY;
    };
    // At a located point a kept factorisation is renewed only when the chord would not reach its
    // goal two iterations before the limit: a few more solves are cheaper than a factorisation.
    // A step keeps the rate rule unless renewal_cost is set: then its chord goes on where it
    // needs fewer solves than a renewal costs (and reaches its goal two before the limit).
    if (located_kept && k > 0) refactor = k + more_at_its_rate() > options_.max_iterations - 2;
    if (costed_step && k > 0 && refactor) {
      const double more = more_at_its_rate();
      if (more <= options_.renewal_cost && k + more <= options_.max_iterations - 2) refactor = false;
    }
    // near the rounding floor a slower fall is rounding, not an old matrix: no new factorisation
    // (a located point's chord on a kept factorisation has its own rule above, which near the
    // tolerance asks for few iterations anyway)
    if (chord && !slow_chord_allowed && k > 0 && normF <= 1e3 * tol) refactor = false;
    if (k == 0 && options_.reuse_factorisation && reusable_ && bordered_->block_factorised())
      refactor = !bordered_->set_row(c.cu, c.cl).is_ok();
    before_previous = previous;
    previous = normF;
    double N = c.cl * (lambda - c.l0) - c.target;
    if (c.cu.size()) N += c.cu.dot(u - *c.u0);
    // Deuflhard's monotonicity test for a step: after an iteration on a Jacobian made at its own
    // iterate (a Newton iteration), the simplified Newton correction -J^-1 F on that same
    // factorisation must be shorter than the Newton correction, or the step started outside
    // Newton's region of contraction and a shorter one is cheaper than more Jacobians (a step had
    // renewed the Jacobian at every iteration until an element inverted, up to 9 factorisations).
    // In the arclength norm of the corrections, not in |F|, whose rows scale unevenly. Where the
    // factorisation is kept, the simplified correction is this iteration's update: no extra solve.
    bool have_update = false;
    if (step && chord && newton_iteration && newton_correction > 0) {
      st = bordered_->solve(-F_, -N, du, dl, false);
      if (!st.is_ok()) return st;
      const double theta = std::sqrt(dot(du, dl, du, dl)) / newton_correction;
      if (!(theta < 1.0))
        return {StatusCode::Diverged,
                fmt::format("corrector: the simplified Newton correction is {:.3g} times the Newton correction "
                            "(monotonicity test)",
                            theta)};
      have_update = !refactor;
    }
    newton_iteration = refactor;
    if (refactor) {
      refactored_ = true;
      st = timed_jacobian(u);
      if (!st.is_ok()) return st;
      st = timed_parameter_derivative(u);
      if (!st.is_ok()) return st;
      bordered_->set(J_, Fp_, c.cu, c.cl);
      st = factorise(u, lambda);
      if (!st.is_ok()) return st;
      ++factorisations_;
      on_this_matrix = 0;
      mixer.reset();
    }
    ++on_this_matrix;
    // the chord iteration corrects the error of an unrefined solve like that of its old matrix
    if (!have_update) st = bordered_->solve(-F_, -N, du, dl, !chord);
    if (!st.is_ok()) return st;
    if (refactor) newton_correction = std::sqrt(dot(du, dl, du, dl));
    // (the unaccelerated update: the accelerated one may be small where the chord is not)
    update = std::max(du.lpNorm<Eigen::Infinity>(), std::abs(dl));
    mixer.mix(u, lambda, du, dl);
    u += du;
    lambda += dl;
    ++iterations;
    if (!u.allFinite() || !std::isfinite(lambda)) return {StatusCode::NotFinite, "corrector produced a non-finite state"};
  }
}

Status Continuation::tangent_from_factorisation(const Vector& tu_prev, double tl_prev, Vector& tu, double& tl,
                                                int& det_sign) {
  Vector v;
  double mu = 0;
  Status st = bordered_->solve(Vector::Zero(problem_.size()), 1.0, v, mu);
  if (!st.is_ok()) return st;
  return unit_tangent(std::move(v), mu, tu_prev, tl_prev, tu, tl, det_sign);
}

Status Continuation::unit_tangent(Vector v, double mu, const Vector& tu_prev, double tl_prev, Vector& tu, double& tl,
                                  int& det_sign) const {
  // (v, mu) solves [J F_p; c^T d] (v, mu) = (0, 1). Cramer: mu = det(J) / det(bordered), so this
  // is the sign of det J
  det_sign = sign_of(mu) * bordered_->determinant_sign();
  const double nrm = std::sqrt(dot(v, mu, v, mu));
  if (!(nrm > 0) || !std::isfinite(nrm)) return {StatusCode::NotFinite, "tangent is zero or not finite"};
  const double sign = tu_prev.size() && dot(v, mu, tu_prev, tl_prev) < 0 ? -1.0 : 1.0;
  tu = (sign / nrm) * v;
  tl = sign * mu / nrm;
  return {};
}

Status Continuation::factorize_at(const Vector& u, double lambda, const Constraint& c) {
  Status st = set_parameter(lambda);
  if (st.is_ok()) st = timed_jacobian(u);
  if (st.is_ok()) st = timed_parameter_derivative(u);
  if (!st.is_ok()) return st;
  bordered_->set(J_, Fp_, c.cu, c.cl);
  st = factorise(u, lambda);
  if (!st.is_ok()) return st;
  ++factorisations_;
  reusable_ = true;
  return {};
}

Status Continuation::factorise(const Vector& u, double lambda) {
  j_lambda_ = NAN;
  const Status st = bordered_->factorize();
  if (st.is_ok()) {
    j_u_ = u;
    j_lambda_ = lambda;
  }
  return st;
}

SparseLU* Continuation::factorisation_at(const BranchPoint& p) {
  if (!(j_lambda_ == p.lambda) || j_u_.size() != p.u.size() || j_u_ != p.u) return nullptr;
  return bordered_->j_factorisation();
}

Status Continuation::point_tangent(BranchPoint& p, const Constraint& c, const Vector& tu_prev, double tl_prev,
                                   bool refresh) {
  if (!options_.reuse_factorisation) {
    if (refresh) {
      const Status st = factorize_at(p.u, p.lambda, c);
      if (!st.is_ok()) return st;
    }
    return tangent_from_factorisation(tu_prev, tl_prev, p.tu, p.tlambda, p.det_sign);
  }
  // the determinant (branch points) needs a factorisation at the point itself; so does a kept
  // factorisation that has grown too old (refresh)
  bool converged = false;
  if (!refresh && !options_.detect_branch_points && bordered_->block_factorised()) {
    // Richardson iteration on [J F_p; c^T d] z = (0, 1) at p, preconditioned by the kept
    // factorisation (possibly of an earlier point): converges while that is close to this one.
    // J v by central differences of the residual (two residuals instead of a Jacobian; error
    // about 1e-11 of |J| |v|, below the 1e-9 the iteration asks for).
    Status st = set_parameter(p.lambda);
    if (st.is_ok()) st = timed_parameter_derivative(p.u);
    if (!st.is_ok()) return st;
    const int n = problem_.size();
    const Vector cu = c.cu.size() ? c.cu : Vector::Zero(n);
    const double scale_j = J_.coeffs().cwiseAbs().maxCoeff();  // of the last assembled Jacobian
    const double scale_a = scale_j + Fp_.cwiseAbs().maxCoeff() + cu.cwiseAbs().maxCoeff() + std::abs(c.cl);
    const double ustep = std::cbrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, p.u.lpNorm<Eigen::Infinity>());
    Vector fplus, fminus;
    auto jacobian_times = [&](const Vector& v, Vector& out) -> Status {
      const double vmax = v.lpNorm<Eigen::Infinity>();
      if (!(vmax > 0)) {
        out = Vector::Zero(n);
        return {};
      }
      const double eps = ustep / vmax;
      const auto t0 = std::chrono::steady_clock::now();
      Status s1 = problem_.residual(p.u + eps * v, fplus);
      if (s1.is_ok()) s1 = problem_.residual(p.u - eps * v, fminus);
      timings_.residual += seconds_since(t0);
      timings_.residuals += 2;
      if (!s1.is_ok()) return s1;
      out = (fplus - fminus) / (2.0 * eps);
      return {};
    };
    Vector v = Vector::Zero(n), rf = Vector::Zero(n), dv, jv;
    double mu = 0.0, rg = 1.0, dmu = 0.0, previous = INFINITY, before_previous = INFINITY;
    // as many iterations as the corrector may make, while each halves the residual and the
    // rate says the tolerance is within reach
    const int limit = std::max(12, options_.max_iterations);
    // accelerated like the corrector's chord (anderson_depth): on this linear system that is
    // GMRES with the kept factorisation as preconditioner
    AndersonMixer mixer(options_.anderson_depth);
    double best = INFINITY, first = INFINITY;
    int it_best = -1;
    for (int it = 0; it < limit; ++it) {
      st = bordered_->solve(rf, rg, dv, dmu, false);
      ++tangent_iterations_;
      if (!st.is_ok()) break;
      mixer.mix(v, mu, dv, dmu);
      v += dv;
      mu += dmu;
      st = jacobian_times(v, jv);
      if (!st.is_ok()) break;
      rf = -(jv + Fp_ * mu);
      rg = 1.0 - cu.dot(v) - c.cl * mu;
      const double res = rf.cwiseAbs().maxCoeff() + std::abs(rg);
      const double scale = 1.0 + scale_a * (v.cwiseAbs().maxCoeff() + std::abs(mu));
      // diverging or stalling: plain Richardson must halve the residual at every iteration;
      // accelerated, which need not fall at every iteration, must find a new least residual
      // every three (an iteration costs a solve and two residuals, a factorisation about 25)
      if (res < best) {
        best = res;
        it_best = it;
      }
      const bool accelerated = mixer.depth() > 0;
      const bool stalled = accelerated ? it - it_best >= 3 || !(res <= 10.0 * best) : !(res <= 0.5 * previous);
      if (it == 0) first = res;
      if (stalled || !std::isfinite(res)) break;
      if (res <= 1e-9 * scale) {
        converged = true;
        break;
      }
      // (the rate over the last two iterations, one alone wanders; accelerated, the mean rate to
      // the least residual so far, as its residual need not fall at every iteration)
      const double rate =
          accelerated ? std::pow(best / first, 1.0 / std::max(it_best, 1)) : std::sqrt(res / before_previous);
      if (it > 1 && rate < 1.0 && it + 1 + std::log(1e-9 * scale / (accelerated ? best : res)) / std::log(rate) > limit)
        break;
      before_previous = previous;
      previous = res;
    }
    // converged: the tangent is this point's, but the sign of det J is not: convergence on
    // another point's factorisation does not show that no eigenvalue crossed zero in between
    // (accelerated, the iteration converges past such a crossing; where F_p = 0 it is exact
    // from any matrix). So 0, not determined here; branch points, which need the sign, get a
    // factorisation at every point.
    if (converged) {
      const Status su = unit_tangent(std::move(v), mu, tu_prev, tl_prev, p.tu, p.tlambda, p.det_sign);
      p.det_sign = 0;
      return su;
    }
  }
  Status st = factorize_at(p.u, p.lambda, c);
  if (!st.is_ok()) return st;
  return tangent_from_factorisation(tu_prev, tl_prev, p.tu, p.tlambda, p.det_sign);
}

Status Continuation::initial_tangent(const Vector& u, double lambda, Vector& tu, double& tl, int& det_sign) {
  Status st = set_parameter(lambda);
  if (st.is_ok()) st = timed_jacobian(u);
  if (st.is_ok()) st = timed_parameter_derivative(u);
  if (!st.is_ok()) return st;
  // [J F_p; 0 1] gives (-J^-1 F_p, 1) where J is regular; at a fold J is singular and a generic
  // border row (0 on the parameter) is used instead.
  bordered_->set(J_, Fp_, Vector(), 1.0);
  st = factorise(u, lambda);
  if (st.code() == StatusCode::SingularMatrix) {
    Vector w(problem_.size());
    for (int i = 0; i < w.size(); ++i) w[i] = std::sin(1.0 + 0.7 * i);  // deterministic, generic
    bordered_->set(J_, Fp_, w, 0.0);
    st = factorise(u, lambda);
  }
  if (!st.is_ok()) return st;
  ++factorisations_;
  reusable_ = true;
  st = tangent_from_factorisation(Vector(), 0.0, tu, tl, det_sign);
  if (!st.is_ok()) return st;
  if (tl * options_.direction < 0) {
    tu = -tu;
    tl = -tl;
  }
  return {};
}

Status Continuation::timed_jacobian(const Vector& u) {
  const auto t0 = std::chrono::steady_clock::now();
  Status st = problem_.jacobian(u, F_, J_);
  timings_.jacobian += seconds_since(t0);
  ++timings_.jacobians;
  return st;
}

Status Continuation::timed_parameter_derivative(const Vector& u) {
  const auto t0 = std::chrono::steady_clock::now();
  Status st = problem_.parameter_derivative(p_, u, Fp_);
  timings_.parameter_derivative += seconds_since(t0);
  return st;
}

void Continuation::analyse(BranchPoint& p) {
  // the analysis of a converged point; its failure is recorded, never a rejected step
  const auto t0 = std::chrono::steady_clock::now();
  Status st = set_parameter(p.lambda);
  PointAnalysisResult r;
  SparseLU* shared = st.is_ok() ? factorisation_at(p) : nullptr;
  const double solve_seconds0 = bordered_->solve_seconds();
  const long solves0 = bordered_->solves();
  if (st.is_ok()) st = analysis_->analyse(problem_, p.u, r, shared);
  // solves with the shared factorisation are the analysis's time, not the continuation's
  shared_solve_seconds_ += bordered_->solve_seconds() - solve_seconds0;
  shared_solves_ += bordered_->solves() - solves0;
  timings_.analysis += seconds_since(t0);
  ++timings_.analyses;
  p.analysed = true;
  p.analysis = std::move(r.columns);
  p.analysis.resize(analysis_->column_names().size(), NAN);
  p.count = st.is_ok() ? r.count : -1;
  p.locator = r.locator;
  p.critical_imag = r.critical_imag;
  p.critical_re = std::move(r.critical_re);
  p.critical_im = std::move(r.critical_im);
  if (!st.is_ok()) analysis_note_ = "analysis failed: " + st.describe();
}

Status Continuation::evaluate(BranchPoint& p, bool analyse_point) {
  if (analyse_point && analysis_) analyse(p);
  const auto t0 = std::chrono::steady_clock::now();
  struct Add {
    double& to;
    std::chrono::steady_clock::time_point t0;
    ~Add() { to += seconds_since(t0); }
  } add{timings_.observables, t0};
  Status st = set_parameter(p.lambda);
  if (st.is_ok()) st = problem_.observables(p.u, p.observables);
  if (st.is_ok()) st = problem_.monitors(p.u, p.monitors);
  if (!st.is_ok()) return st;
  for (double v : p.observables)
    if (!std::isfinite(v)) return {StatusCode::NotFinite, "an observable is not finite"};
  // the stop observable's distance to its thresholds is monitored like the problem's monitors
  if (stop_index_ >= 0) {
    if (std::isfinite(options_.stop_above)) p.monitors.push_back(p.observables[stop_index_] - options_.stop_above);
    if (std::isfinite(options_.stop_below)) p.monitors.push_back(p.observables[stop_index_] - options_.stop_below);
  }
  for (double v : p.monitors)
    if (!std::isfinite(v)) return {StatusCode::NotFinite, "a monitor is not finite"};
  p.seconds = seconds_since(t_start_);
  return {};
}

std::vector<double> Continuation::monitor_values(const BranchPoint& p) const { return p.monitors; }

BranchPoint Continuation::point_on_segment(const BranchPoint& a, const BranchPoint& b, double tau, Status& st,
                                           const BranchPoint* lo, const BranchPoint* hi, bool exact_tangent,
                                           bool analyse) {
  // where the target lies along the segment, in the coordinate the constraint fixes
  const bool arclength = options_.method == ContinuationOptions::Method::Arclength;
  auto coord = [&](const BranchPoint& p) {
    return arclength ? dot(p.u - a.u, p.lambda - a.lambda, a.tu, a.tlambda) : p.lambda;
  };
  const double target = arclength ? tau * coord(b) : a.lambda + tau * (b.lambda - a.lambda);
  // predictor: interpolation between the closest points known on the branch (the bracket)
  const BranchPoint& p0 = lo ? *lo : a;
  const BranchPoint& p1 = hi ? *hi : b;
  const double c0 = coord(p0), c1 = coord(p1);
  const double w = c1 != c0 ? (target - c0) / (c1 - c0) : tau;
  BranchPoint p;
  // the cubic Hermite interpolant of the bracket (see locate_value) where it has the target
  // coordinate; the chord between them where it has none
  const BranchFunctional coordinate = [&](const Vector& u, double l, bool point) {
    if (!arclength) return l;
    return point ? dot(u - a.u, l - a.lambda, a.tu, a.tlambda) : dot(u, l, a.tu, a.tlambda);
  };
  double x = w;
  const bool cubic = hermite_point(p0, p1, coordinate, target, p.u, p.lambda, x);
  if (!cubic) {
    p.u = p0.u + w * (p1.u - p0.u);
    p.lambda = p0.lambda + w * (p1.lambda - p0.lambda);
  }
  const Constraint c = arclength ? arclength_constraint(a, a.tu, a.tlambda, target) : lambda_constraint(target);
  located_floor_ = residual_floor(p0.residual, p1.residual);
  st = correct(p.u, p.lambda, c, p.iterations);
  located_floor_ = 0.0;
  p.residual = last_residual_;
  // The corrector's last factorisation is at its second-last iterate. Locating a fold (a zero of
  // the tangent's parameter part) or a sign change of the determinant needs them at the point
  // itself: one more factorisation there.
  if (st.is_ok() && exact_tangent) {
    st = factorize_at(p.u, p.lambda, c);
    if (st.is_ok()) st = tangent_from_factorisation(a.tu, a.tlambda, p.tu, p.tlambda, p.det_sign);
  } else if (st.is_ok()) {
    st = point_tangent(p, c, a.tu, a.tlambda);
  }
  if (st.is_ok()) st = evaluate(p, analyse);
  p.bordered_det_sign = bordered_->determinant_sign();
  // where along the branch: on the cubic, the bracket's fraction x; else the coordinate's
  p.s = cubic ? p0.s + x * (p1.s - p0.s) : a.s + tau * (b.s - a.s);
  p.step = b.step;
  return p;
}

std::optional<BranchPoint> Continuation::locate_value(const BranchPoint& a, const BranchPoint& b, double value) {
  double tau = (value - a.lambda) / (b.lambda - a.lambda);
  BranchPoint p;
  // predictor: the cubic Hermite interpolant of the two points and their tangents (error O(h^4)
  // against O(h^2) for the chord between them), so that the corrector converges on the kept
  // factorisation instead of renewing it; the chord where the cubic does not reach the value
  double x = tau, lambda = value;
  const BranchFunctional parameter = [](const Vector&, double l, bool) { return l; };
  if (hermite_point(a, b, parameter, value, p.u, lambda, x)) tau = x;
  else p.u = a.u + tau * (b.u - a.u);
  p.lambda = value;
  const Constraint c = lambda_constraint(value);
  located_floor_ = residual_floor(a.residual, b.residual);
  Status st = correct(p.u, p.lambda, c, p.iterations);
  located_floor_ = 0.0;
  p.residual = last_residual_;
  if (st.is_ok()) st = point_tangent(p, c, a.tu, a.tlambda);
  if (st.is_ok()) st = evaluate(p, false);
  if (st.is_ok()) {
    p.lambda = value;  // exactly
    p.s = a.s + tau * (b.s - a.s);
    p.step = b.step;
    p.bordered_det_sign = 0;
    return p;
  }
  // at a fold the parameter cannot be fixed: fall back to root finding along the arclength
  const std::string first = st.describe();
  location_note_ = "fixed-parameter corrector failed (" + first + "); ";
  return locate_root(a, b, -3, a.lambda - value, b.lambda - value);
}

// which >= 0: monitor index; -1: fold (parameter part of the tangent); -2: branch point (sign of
// det of the bordered matrix, bisection); -3: lambda - value (value = lambda(a) - ga); -4: change
// of the analysis count (bracket kept by the count, trials by secant on the locator where it
// changes sign across the bracket, else bisection).
std::optional<BranchPoint> Continuation::locate_root(const BranchPoint& a, const BranchPoint& b, int which, double ga,
                                                     double gb) {
  const double value = a.lambda - ga;
  auto g_of = [&](const BranchPoint& p) -> double {
    if (which >= 0) return monitor_values(p)[static_cast<size_t>(which)];
    if (which == -1) return p.tlambda;
    if (which == -2) return static_cast<double>(p.bordered_det_sign);
    if (which == -4) return p.locator;
    return p.lambda - value;
  };
  const bool by_count = which == -4;
  const int count_a = a.count;
  const bool sign_only = which == -2;
  const bool turning = which == -1 || which == -2 || by_count;
  double ta = 0.0, tb = 1.0;
  BranchPoint pa = a, pb = b;
  int side = 0, solves = 0;
  double t_before = NAN;
  double last_lambda = NAN;
  for (int it = 0; it < options_.max_location_iterations; ++it) {
    const bool secant = !sign_only && (!by_count || (std::isfinite(ga) && std::isfinite(gb) && ga * gb < 0));
    double tc = secant ? tb - gb * (tb - ta) / (gb - ga) : 0.5 * (ta + tb);
    // a trial on or outside the bracket (rounding) falls back to bisection
    if (!(tc > ta && tc < tb)) tc = 0.5 * (ta + tb);
    Status st;
    const double lambda_before = it > 0 ? last_lambda : NAN;
    BranchPoint pc = point_on_segment(a, b, tc, st, &pa, &pb, which == -1 || which == -2, by_count);
    solves += pc.iterations;
    last_lambda = pc.lambda;
    if (!st.is_ok()) {
      location_note_ += "corrector failed while locating: " + st.describe();
      return std::nullopt;
    }
    const double gc = g_of(pc);
    if (by_count && pc.count < 0) {
      location_note_ += "analysis failed while locating: " + analysis_note_;
      return std::nullopt;
    }
    if (gc == 0.0 && !sign_only && !by_count) {
      pc.iterations = solves;
      return pc;
    }
    const bool same_side = by_count ? pc.count == count_a : sign_of(gc) == sign_of(ga);
    if (same_side) {
      ta = tc;
      ga = gc;
      pa = pc;
      if (side == -1 && !sign_only) gb *= 0.5;  // Illinois: the retained end's value is halved
      side = -1;
    } else {
      tb = tc;
      gb = gc;
      pb = pc;
      if (side == +1 && !sign_only) ga *= 0.5;
      side = +1;
    }
    double width = std::abs(pa.lambda - pb.lambda);
    if (turning) width = std::max(width, std::abs(pb.s - pa.s) * std::max(std::abs(pa.tlambda), std::abs(pb.tlambda)));
    // a zero of a monitor is also found once successive secant trials agree to the tolerance
    bool settled = !turning && std::abs(pc.lambda - lambda_before) <= options_.event_tolerance;
    // a count change located by secant on its locator: successive trials agree along the branch
    if (by_count && it > 0) settled = std::abs(tc - t_before) * std::abs(b.s - a.s) <= options_.event_tolerance;
    t_before = tc;
    if (settled) {
      pc.iterations = solves;
      return pc;
    }
    if (width <= options_.event_tolerance) {
      BranchPoint& best = by_count  ? (std::abs(pa.locator) < std::abs(pb.locator) ? pa : pb)
                          : turning ? (std::abs(pa.tlambda) < std::abs(pb.tlambda) ? pa : pb)
                                    : (std::abs(g_of(pa)) < std::abs(g_of(pb)) ? pa : pb);
      best.iterations = solves;
      return best;
    }
  }
  location_note_ += fmt::format("not located to {} in {} iterations", options_.event_tolerance,
                                options_.max_location_iterations);
  return std::nullopt;
}

void Continuation::report(BranchObserver& observer, const BranchPoint& p) {
  const auto t0 = std::chrono::steady_clock::now();
  observer.on_point(p);
  timings_.output += seconds_since(t0);
}

ContinuationResult Continuation::run(const Vector& u0, BranchObserver& observer) {
  t_start_ = std::chrono::steady_clock::now();
  const double rms = u0.size() ? u0.norm() / std::sqrt(static_cast<double>(u0.size())) : 0.0;
  state_scale_ = options_.state_scale > 0 ? options_.state_scale : (rms > 0 ? rms : 1.0);
  wu_ = options_.theta / (static_cast<double>(problem_.size()) * state_scale_ * state_scale_);
  wl_ = 1.0 - options_.theta;
  BranchPoint start;
  start.kind = PointKind::Start;
  start.u = u0;
  start.lambda = problem_.parameters().value(p_);
  start.step = options_.initial_step;
  Status st = initial_tangent(start.u, start.lambda, start.tu, start.tlambda, start.det_sign);
  if (!st.is_ok()) {
    ContinuationResult r;
    r.code = StopCode::StepFloor;
    r.reason = "no tangent at the starting point: " + st.describe();
    return r;
  }
  return trace(std::move(start), observer);
}

ContinuationResult Continuation::resume(BranchPoint start, BranchObserver& observer) {
  t_start_ = std::chrono::steady_clock::now();
  if (!(options_.state_scale > 0)) throw std::invalid_argument("resume needs the state scale of the original run");
  if (start.u.size() != problem_.size() || start.tu.size() != problem_.size())
    throw std::invalid_argument(fmt::format("stored point has {} unknowns, the problem {}", start.u.size(), problem_.size()));
  state_scale_ = options_.state_scale;
  wu_ = options_.theta / (static_cast<double>(problem_.size()) * state_scale_ * state_scale_);
  wl_ = 1.0 - options_.theta;
  start.kind = PointKind::Start;
  return trace(std::move(start), observer);
}

ContinuationResult Continuation::switch_branch(BranchPoint bp, int direction, BranchObserver& observer) {
  t_start_ = std::chrono::steady_clock::now();
  if (!(options_.state_scale > 0)) throw std::invalid_argument("switch_branch needs the state scale of the original run");
  if (bp.u.size() != problem_.size() || bp.tu.size() != problem_.size())
    throw std::invalid_argument(fmt::format("stored point has {} unknowns, the problem {}", bp.u.size(), problem_.size()));
  state_scale_ = options_.state_scale;
  wu_ = options_.theta / (static_cast<double>(problem_.size()) * state_scale_ * state_scale_);
  wl_ = 1.0 - options_.theta;
  ContinuationResult result;
  auto fail = [&](const std::string& why) {
    result.code = StopCode::StepFloor;
    result.reason = "no branch to switch to: " + why;
    observer.on_finish(result.reason, bp);
    return result;
  };
  // the null vector of J at the branch point by inverse iteration (J is nearly singular there, so
  // each solve multiplies its share by the inverse of the smallest singular value)
  Status st = set_parameter(bp.lambda);
  if (st.is_ok()) st = timed_jacobian(bp.u);
  if (!st.is_ok()) return fail(st.describe());
  SparseLU lu(lu_options_);
  st = lu.factorize(J_);
  if (!st.is_ok()) return fail("J at the branch point: " + st.describe());
  Vector phi(problem_.size());
  for (int i = 0; i < phi.size(); ++i) phi[i] = std::sin(1.0 + 0.7 * i);
  for (int it = 0; it < 3; ++it) {
    Vector y;
    st = lu.solve(phi, y);
    if (!st.is_ok()) return fail(st.describe());
    phi = y / y.norm();
  }
  // a fixed sign: the entry of largest magnitude positive (direction +1 makes it grow)
  Eigen::Index imax = 0;
  phi.cwiseAbs().maxCoeff(&imax);
  if (phi[imax] < 0) phi = -phi;
  // (phi, 0) lies in the null space of [J F_p] there, as the old tangent does: the new direction is
  // its part orthogonal to the old tangent
  const double along = dot(phi, 0.0, bp.tu, bp.tlambda);
  Vector tu = phi - along * bp.tu;
  double tl = -along * bp.tlambda;
  const double nrm = std::sqrt(dot(tu, tl, tu, tl));
  if (!(nrm > 0) || !std::isfinite(nrm)) return fail("the null vector of J is the old tangent");
  BranchPoint start = bp;
  start.tu = (direction >= 0 ? 1.0 : -1.0) * tu / nrm;
  start.tlambda = (direction >= 0 ? 1.0 : -1.0) * tl / nrm;
  start.kind = PointKind::Start;
  start.label = "switched";
  start.s = 0.0;
  start.step = options_.initial_step;
  start.analysed = false;
  return trace(std::move(start), observer);
}

ContinuationResult Continuation::trace(BranchPoint start, BranchObserver& observer) {
  const bool arclength = options_.method == ContinuationOptions::Method::Arclength;
  ContinuationResult result;
  next_index_ = 0;
  last_count_ = -1;
  last_count_index_ = -1;
  last_analysed_.reset();
  unanalysed_.clear();
  observer.on_start(problem_.observable_names(), monitor_names_);

  // the start: observables, the sign of det of the bordered matrix with its own tangent, and
  // the analysis (with that factorisation of J)
  Status st = evaluate(start, false);
  // J's block factorisation made at this very point for the initial tangent (run) takes the
  // arclength row through its Schur complement: no second factorisation of the same matrix
  const bool factorised_here = arclength && bordered_->block_factorised() && factorisation_at(start) != nullptr;
  if (st.is_ok()) st = arclength && !factorised_here ? timed_jacobian(start.u) : problem_.residual(start.u, F_);
  if (st.is_ok()) start.residual = F_.lpNorm<Eigen::Infinity>();
  if (st.is_ok() && factorised_here && bordered_->set_row(wu_ * start.tu, wl_ * start.tlambda).is_ok()) {
    reusable_ = true;
    start.bordered_det_sign = bordered_->determinant_sign();
  } else if (st.is_ok() && arclength) {
    st = timed_parameter_derivative(start.u);
    if (st.is_ok()) {
      bordered_->set(J_, Fp_, wu_ * start.tu, wl_ * start.tlambda);
      st = factorise(start.u, start.lambda);
      ++factorisations_;
      reusable_ = st.is_ok();
      start.bordered_det_sign = st.is_ok() ? bordered_->determinant_sign() : 0;
      st = {};
    }
  }
  if (st.is_ok() && analysis_) analyse(start);
  if (!st.is_ok()) {
    result.code = StopCode::StepFloor;
    result.reason = "the starting point cannot be evaluated: " + st.describe();
    return result;
  }
  start.index = next_index_++;
  start.save = true;
  // a switched branch starts on the branch point itself, where the count is either value
  if (start.analysed && start.count >= 0 && start.label != "switched") {
    last_count_ = start.count;
    last_count_index_ = start.index;
    if (analysis_ && analysis_->every() > 1) last_analysed_ = start;
  }
  report(observer, start);

  auto finish = [&](StopCode code, std::string reason, const BranchPoint& last) {
    result.code = code;
    result.reason = std::move(reason);
    result.points = next_index_;
    result.factorisations = factorisations_;
    result.tangent_iterations = tangent_iterations_;
    timings_.factorisation = bordered_->factor_seconds();
    timings_.solve = bordered_->solve_seconds() - shared_solve_seconds_;
    timings_.solves = bordered_->solves() - shared_solves_;
    timings_.total = seconds_since(t_start_);
    result.timings = timings_;
    result.last = last;
    observer.on_finish(result.reason, last);
    return result;
  };

  BranchPoint cur = std::move(start);
  std::optional<BranchPoint> prev;
  landing_failed_ = false;
  double ds = std::clamp(cur.step, options_.min_step, options_.max_step);
  const double max_angle = options_.max_angle_degrees * M_PI / 180.0;
  int steps = 0;
  while (true) {
    if (stop_requested_.load()) return finish(StopCode::Interrupted, "interrupted by a signal", cur);
    if (steps >= options_.max_steps)
      return finish(StopCode::MaxSteps, fmt::format("max_steps = {} reached", options_.max_steps), cur);

    // predictor
    Vector du_dir = cur.tu;
    double dl_dir = cur.tlambda;
    if (options_.predictor == ContinuationOptions::Predictor::Secant && prev) {
      du_dir = cur.u - prev->u;
      dl_dir = cur.lambda - prev->lambda;
      const double nrm = std::sqrt(dot(du_dir, dl_dir, du_dir, dl_dir));
      du_dir /= nrm;
      dl_dir /= nrm;
    }
    BranchPoint nxt;
    Constraint c;
    const std::optional<Landing> land = landing(cur, prev ? &*prev : nullptr, ds, dl_dir);
    if (land) {
      // shortened to land on a stop or a bound: predicted along the same direction, corrected at
      // that parameter value; its tangent is taken under the step's own border row (below)
      nxt.lambda = land->value;
      nxt.u = cur.u + ((land->value - cur.lambda) / dl_dir) * du_dir;
      c = lambda_constraint(land->value);
    } else if (arclength) {
      nxt.u = cur.u + ds * du_dir;
      nxt.lambda = cur.lambda + ds * dl_dir;
      c = arclength_constraint(cur, du_dir, dl_dir, ds);
    } else {
      const double dlam = options_.direction * ds;
      nxt.lambda = cur.lambda + dlam;
      nxt.u = std::abs(dl_dir) > 1e-12 ? Vector(cur.u + (dlam / dl_dir) * du_dir) : cur.u;
      c = lambda_constraint(nxt.lambda);
    }
    step_floor_ = residual_floor(cur.residual, prev ? prev->residual : 0.0);
    st = correct(nxt.u, nxt.lambda, c, nxt.iterations, true);
    nxt.residual = last_residual_;
    // A chord on a kept factorisation that needed more iterations than the target without
    // failing its rate does not shrink the step: the step was not too long, the matrix was old.
    // (Nor is the matrix renewed here: the next step's chord renews it if its rate fails. A
    // renewal at the point cost one factorisation per such step, and the chord of the next step
    // on it converged no faster: 12 factorisations for 10 rows instead of 7 for 8, M2 t branch.)
    const bool stale = options_.reuse_factorisation && !refactored_ && nxt.iterations > options_.target_iterations;
    // (the last step analyses its point too, so that no change of the count goes unchecked)
    const bool analyse_now =
        analysis_ && ((steps + 1) % std::max(analysis_->every(), 1) == 0 || steps + 1 >= options_.max_steps);
    // a point about to be analysed gets J's factorisation at itself (block elimination): the
    // tangent is then exact and the analysis solves with it instead of factorising J again
    const bool share = analyse_now && options_.block_elimination && analysis_->uses_j_factorisation();
    if (st.is_ok() && land) {
      // the tangent (and the sign of det of the bordered matrix, for branch points) under the
      // pseudo-arclength border row, as at every other point of the branch
      c = arclength_constraint(cur, du_dir, dl_dir, ds);
      if (options_.reuse_factorisation && bordered_->block_factorised()) st = bordered_->set_row(c.cu, c.cl);
    }
    // (without a kept factorisation the landed point's own one has the parameter row: a new one
    // under the pseudo-arclength row, or the sign of det flips with the sign of the parameter
    // part of the tangent and passes for a branch point)
    if (st.is_ok())
      st = point_tangent(nxt, c, cur.tu, cur.tlambda, share || (land && !options_.reuse_factorisation));
    if (!st.is_ok()) reusable_ = false;
    // a sharp turn of the tangent means the step skipped a feature of the branch or, in natural
    // continuation, jumped to another branch past a fold
    if (st.is_ok()) {
      const double angle = std::acos(std::clamp(dot(nxt.tu, nxt.tlambda, cur.tu, cur.tlambda), -1.0, 1.0));
      if (angle > max_angle && ds > options_.min_step)
        st = {StatusCode::NotConverged, fmt::format("tangent turned by {:.1f} degrees", angle * 180.0 / M_PI)};
    }
    if (st.is_ok()) st = evaluate(nxt, analyse_now);
    if (!st.is_ok()) {
      if (land) landing_failed_ = true;
      ++result.rejected;
      observer.on_rejected(nxt.lambda, ds, st);
      ds *= 0.5;
      if (ds < options_.min_step)
        return finish(StopCode::StepFloor,
                      fmt::format("step size fell below min_step = {} at {} = {:.10g}: {}", options_.min_step,
                                  options_.parameter, cur.lambda, st.describe()),
                      cur);
      continue;
    }
    ++steps;
    landing_failed_ = false;
    nxt.bordered_det_sign = arclength ? bordered_->determinant_sign() : 0;
    if (arclength && !land) {
      nxt.s = cur.s + ds;
    } else {
      const Vector du = nxt.u - cur.u;
      const double dl = nxt.lambda - cur.lambda;
      nxt.s = cur.s + std::sqrt(dot(du, dl, du, dl));
    }
    double ds_next = ds;
    // (a step shortened to land on a value says nothing for a longer one: not grown)
    if (nxt.iterations < options_.target_iterations && !land) ds_next = ds * options_.growth;
    else if (nxt.iterations > options_.target_iterations && !stale) ds_next = ds * std::max(options_.shrink, 0.7);
    ds_next = std::clamp(ds_next, options_.min_step, options_.max_step);
    nxt.step = ds_next;

    // everything located on the segment cur -> nxt, in order along the branch
    struct Located {
      BranchPoint point;
      bool terminal;
      StopCode code;
    };
    std::vector<Located> located;
    auto add = [&](std::optional<BranchPoint> p, PointKind kind, std::string label, bool terminal, StopCode code) {
      if (!p) {
        observer.on_note(fmt::format("{} '{}' detected after row {} but not located: {}", to_string(kind), label,
                                     cur.index, location_note_));
        location_note_.clear();
        return;
      }
      location_note_.clear();
      // located points get their spectrum with every point analysed (with every N > 1 they cost
      // one spectrum each, more than the branch's own: left out)
      if (analysis_ && !p->analysed && analysis_->every() == 1) analyse(*p);
      p->kind = kind;
      p->label = std::move(label);
      located.push_back({std::move(*p), terminal, code});
    };
    if (cur.lambda <= options_.upper && nxt.lambda > options_.upper)
      add(locate_value(cur, nxt, options_.upper), PointKind::End, "upper", true, StopCode::UpperBound);
    if (cur.lambda >= options_.lower && nxt.lambda < options_.lower)
      add(locate_value(cur, nxt, options_.lower), PointKind::End, "lower", true, StopCode::LowerBound);
    for (double v : options_.stops)
      if (!(land && v == land->value) &&
          ((cur.lambda - v) * (nxt.lambda - v) < 0 || (nxt.lambda == v && cur.lambda != v)))
        add(locate_value(cur, nxt, v), PointKind::Requested, fmt::format("{} = {}", options_.parameter, v), false,
            StopCode::MaxSteps);
    const std::vector<double> gc = monitor_values(cur), gn = monitor_values(nxt);
    const size_t n_problem_monitors = problem_.monitor_names().size();
    std::vector<std::optional<BranchPoint>> zero_of(gc.size());  // located on this step, by monitor
    for (size_t k = 0; k < gc.size(); ++k) {
      // a zero exactly at nxt (a step that landed on a stop where a monitor vanishes) is this
      // step's, located at nxt itself; the next step starts on it and does not count it again
      const bool at_next = gn[k] == 0.0 && gc[k] != 0.0;
      if (!(gc[k] * gn[k] < 0) && !at_next) continue;
      const bool stop = k >= n_problem_monitors;
      std::optional<BranchPoint> p;
      if (at_next) {
        p = nxt;
        p->iterations = 0;
      } else {
        // the same function as a monitor located before on this step (a stop observable on a
        // problem monitor with threshold 0): the same zero, not a second search
        for (size_t j = 0; j < k && !p; ++j)
          if (zero_of[j] && gc[j] == gc[k] && gn[j] == gn[k]) p = zero_of[j];
        if (!p) p = locate_root(cur, nxt, static_cast<int>(k), gc[k], gn[k]);
      }
      const size_t before = located.size();
      add(std::move(p), stop ? PointKind::End : PointKind::Event, monitor_names_[k], stop, StopCode::StopObservable);
      if (located.size() > before) zero_of[k] = located.back().point;  // (analysed, if it was)
    }
    if (arclength && options_.detect_folds && cur.tlambda * nxt.tlambda < 0)
      add(locate_root(cur, nxt, -1, cur.tlambda, nxt.tlambda), PointKind::Fold, cur.tlambda > 0 ? "max" : "min",
          false, StopCode::MaxSteps);
    if (arclength && options_.detect_branch_points && cur.bordered_det_sign * nxt.bordered_det_sign < 0)
      add(locate_root(cur, nxt, -2, cur.bordered_det_sign, nxt.bordered_det_sign), PointKind::BranchPoint,
          "det sign change", false, StopCode::MaxSteps);
    // a branch that ends on this step: its last stretch is checked too (analysis every N points)
    if (analysis_ && !nxt.analysed &&
        ((land && land->terminal) ||
         std::any_of(located.begin(), located.end(), [](const Located& l) { return l.terminal; })))
      analyse(nxt);
    // changes of the analysis count (stability): a real eigenvalue through zero is a fold where the
    // parameter turns, else a branch point; a complex pair through the imaginary axis a Hopf point.
    // Where the engine located the same fold or branch point on this step itself, that point says
    // so instead.
    if (analysis_ && nxt.analysed) {
      if (last_count_ >= 0 && nxt.count >= 0 && last_count_ != nxt.count) {
        // the analysed pair that brackets the change: cur and nxt, or (analysis every N points)
        // found by bisection over the accepted points since the last analysed one, analysing
        // about log2(N) of them
        BranchPoint* a = &cur;
        BranchPoint* b = &nxt;
        bool bracketed = last_count_index_ == cur.index;
        if (!bracketed && last_analysed_ && last_analysed_->index == last_count_index_ && !unanalysed_.empty() &&
            unanalysed_.back().index == cur.index) {
          std::vector<BranchPoint*> seq{&*last_analysed_};
          for (BranchPoint& q : unanalysed_) seq.push_back(&q);
          seq.push_back(&nxt);
          size_t lo = 0, hi = seq.size() - 1;
          bracketed = true;
          while (hi - lo > 1) {
            const size_t mid = (lo + hi) / 2;
            analyse(*seq[mid]);
            if (seq[mid]->count < 0) {
              bracketed = false;
              break;
            }
            (seq[mid]->count == last_count_ ? lo : hi) = mid;
          }
          a = seq[lo];
          b = seq[hi];
        }
        const std::string change = fmt::format("{} {} -> {}", analysis_->count_name(), a->count, b->count);
        if (!bracketed) {
          observer.on_note(fmt::format("{} between rows {} and {} (not located: analysis every {} points)", change,
                                       last_count_index_, next_index_, analysis_->every()));
        } else {
          const bool fold = a->tlambda * b->tlambda < 0;
          std::optional<BranchPoint> p = locate_root(*a, *b, -4, a->locator, b->locator);
          if (p) {
            const double scale = 1.0 + std::abs(p->locator);
            const bool complex = std::abs(p->critical_imag) > 1e-8 * scale;
            const PointKind kind = complex ? PointKind::Hopf : (fold ? PointKind::Fold : PointKind::BranchPoint);
            std::string label = complex ? fmt::format("omega = {:.8g}, {}", std::abs(p->critical_imag), change)
                                        : fmt::format("eigenvalue crosses zero, {}", change);
            const bool this_step = a == &cur && b == &nxt;
            if (!this_step)
              label += fmt::format(" (bracketed by bisection between {} = {:.8g} and {:.8g})", options_.parameter,
                                   a->lambda, b->lambda);
            auto same = this_step ? std::find_if(located.begin(), located.end(),
                                                 [&](const Located& l) { return l.point.kind == kind; })
                                  : located.end();
            if (same != located.end()) {
              same->point.label += ", " + label;
            } else {
              add(std::move(p), kind, std::move(label), false, StopCode::MaxSteps);
            }
          } else {
            add(std::nullopt, PointKind::Event, change, false, StopCode::MaxSteps);
          }
        }
      }
    }
    if (analysis_ && !analysis_note_.empty()) {
      observer.on_note(fmt::format("after row {}: {}", cur.index, analysis_note_));
      analysis_note_.clear();
    }
    std::stable_sort(located.begin(), located.end(),
                     [](const Located& x, const Located& y) { return x.point.s < y.point.s; });
    const double near = 1e-3 * std::abs(nxt.s - cur.s);
    // a zero found twice (a problem monitor that is also the stop observable: the event and the
    // end are the same point) is reported once, as the end; other kinds are always kept
    {
      auto same_as_an_end = [&](const Located& l) {
        return l.point.kind == PointKind::Event && std::any_of(located.begin(), located.end(), [&](const Located& t) {
          return t.terminal && t.code == StopCode::StopObservable &&
                 std::abs(t.point.lambda - l.point.lambda) <= options_.event_tolerance &&
                 std::abs(t.point.s - l.point.s) <= near;
        });
      };
      std::vector<bool> drop(located.size());
      for (size_t i = 0; i < located.size(); ++i) drop[i] = same_as_an_end(located[i]);
      std::vector<Located> kept;
      for (size_t i = 0; i < located.size(); ++i)
        if (!drop[i]) kept.push_back(std::move(located[i]));
      located = std::move(kept);
    }
    auto bound_reached = [&](const BranchPoint& p) {
      return fmt::format("reached the {} bound {} = {:.10g}", p.label, options_.parameter, p.lambda);
    };
    // nxt's own row (a landed stop or bound is labelled as such)
    bool next_reported = false;
    auto report_next = [&]() {
      next_reported = true;
      nxt.index = next_index_++;
      nxt.save = nxt.index % options_.save_every == 0;
      if (land) {
        nxt.kind = land->kind;
        nxt.label = land->label;
        nxt.save = true;
      }
      if (nxt.analysed && nxt.count >= 0) {
        last_count_ = nxt.count;
        last_count_index_ = nxt.index;
      }
      if (analysis_ && analysis_->every() > 1) {
        if (nxt.analysed) {
          last_analysed_ = nxt;
          unanalysed_.clear();
        } else {
          unanalysed_.push_back(nxt);
        }
      }
      report(observer, nxt);
    };
    for (Located& l : located) {
      // an end found at a landed stop itself comes after the stop's row
      if (l.terminal && land && !land->terminal && std::abs(l.point.s - nxt.s) <= near) report_next();
      l.point.index = next_index_++;
      l.point.save = true;
      report(observer, l.point);
      if (l.terminal) {
        const std::string why = l.code == StopCode::StopObservable
                                    ? fmt::format("{} crossed at {} = {:.10g}", l.point.label, options_.parameter,
                                                  l.point.lambda)
                                    : bound_reached(l.point);
        return finish(l.code, why, l.point);
      }
    }
    if (!next_reported) report_next();
    if (land && land->terminal) return finish(land->code, bound_reached(nxt), nxt);
    prev = std::move(cur);
    cur = std::move(nxt);
    ds = ds_next;
  }
}

}  // namespace keller
