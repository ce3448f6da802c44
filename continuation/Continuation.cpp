#include "continuation/Continuation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "continuation/events/BranchSwitcher.hpp"

namespace keller {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
// Adds the seconds of its scope to a timing.
struct ScopeSeconds {
  double& to;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  ~ScopeSeconds() { to += seconds_since(t0); }
};
ContinuationOptions validated(ContinuationOptions o) {
  o.validate();
  return o;
}
}  // namespace

Continuation::Continuation(Problem& problem, ContinuationOptions options, NewtonOptions newton, SparseLUOptions lu)
    : problem_(problem),
      options_(validated(std::move(options))),
      newton_(newton),
      lu_options_(lu),
      ev_(problem, problem.parameters().index(options_.parameter), options_.parameter),
      kept_(problem, lu, options_.corrector.block_elimination),
      corrector_(ev_, kept_, norm_, options_, newton_),
      tangents_(ev_, kept_, norm_, options_),
      predictor_(options_, norm_),
      steps_(options_.step, options_.target_iterations()),
      locator_(
          corrector_, tangents_, kept_, norm_, options_,
          [this](BranchPoint& p, bool analyse_point) { return evaluate(p, analyse_point); },
          [this]() { return analysis_note_; }),
      lander_(ev_, locator_, options_),
      spectra_(std::make_unique<SpectrumScheduler>(nullptr)) {
  if (!options_.stop.observable.empty()) {
    const auto names = problem_.observable_names();
    auto it = std::find(names.begin(), names.end(), options_.stop.observable);
    if (it == names.end()) {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown observable '" + options_.stop.observable + "'; this problem has: " + known);
    }
    stop_index_ = static_cast<int>(it - names.begin());
  }
  monitor_names_ = problem_.monitor_names();
  turning_ = turning_unknowns(problem_);
  partial_ = partial_monitors(problem_);
  for (const std::string& m : options_.stop.threshold_monitor_names()) monitor_names_.push_back(m);
  lander_.configure(stop_index_, static_cast<int>(problem_.monitor_names().size()), monitor_names_);
}

Continuation::~Continuation() = default;

StartFactorisation Continuation::factorisation() const {
  StartFactorisation f = kept_.inner_factorisation();
  if (f.lu) f.renewal_cost = corrector_.renewal_cost();
  return f;
}

void Continuation::set_analysis(PointAnalysis* analysis) {
  analysis_ = analysis;
  spectra_ = std::make_unique<SpectrumScheduler>(analysis);
}

void Continuation::set_norm(const Vector& u0, double scale) {
  if (!(scale > 0)) {
    const double rms = u0.size() ? u0.norm() / std::sqrt(static_cast<double>(u0.size())) : 0.0;
    scale = rms > 0 ? rms : 1.0;
  }
  norm_ = ArclengthNorm(problem_.size(), scale, options_.theta);
}

ContinuationResult Continuation::run(const Vector& u0, BranchObserver& observer, StartFactorisation factorised,
                                     const BranchPoint* near) {
  t_start_ = std::chrono::steady_clock::now();
  start_on_.reset();
  adopted_ = false;
  resumed_ = false;
  set_norm(u0, options_.state_scale);
  BranchPoint start;
  start.kind = PointKind::Start;
  start.u = u0;
  start.lambda = problem_.parameters().value(ev_.parameter());
  start.step = options_.step.initial;
  Tangent t;
  Status st = {StatusCode::InvalidState, "no factorisation of the start's solve"};
  if (factorised.lu && options_.corrector.kept()) {
    // the tangent system [J F_p; 0 1] at the start, J's factorisation from the solve of the start
    const Constraint row = Constraint::parameter(0.0);
    st = kept_.adopt_at(ev_, factorised, start.u, start.lambda, row);
    factorised = {};  // (held by the kept factorisation alone, where the caller handed it over)
    if (st.is_ok()) {
      // a start solved only to near the tolerance (a switch of an event curve) is finished on the
      // adopted factorisation: a chord iteration or two instead of a solve of its own
      Vector F;
      st = ev_.residual(start.u, F);
      if (st.is_ok() && F.lpNorm<Eigen::Infinity>() > corrector_.tolerance()) {
        double lambda = start.lambda;
        const CorrectorResult r =
            corrector_.correct(start.u, lambda, Constraint::parameter(start.lambda), Corrector::Kind::Located);
        st = r.status;
      }
    }
    if (st.is_ok()) st = tangents_.at_point(start, row, Vector(), 0.0, false, t, near);
    if (st.is_ok() && t.tl * options_.direction < 0) {
      t.tu = -t.tu;
      t.tl = -t.tl;
    }
    adopted_ = st.is_ok() && !t.factorised;
  }
  if (!st.is_ok()) st = tangents_.initial(start.u, start.lambda, t);
  if (!st.is_ok()) {
    ContinuationResult r;
    r.code = StopCode::StartFailed;
    r.reason = "the branch could not start: no tangent at the starting point: " + st.describe();
    return r;
  }
  start.tu = std::move(t.tu);
  start.tlambda = t.tl;
  start.det_sign = t.det_sign;
  return trace(std::move(start), observer);
}

ContinuationResult Continuation::resume(BranchPoint start, BranchObserver& observer) {
  t_start_ = std::chrono::steady_clock::now();
  adopted_ = false;
  if (!(options_.state_scale > 0)) throw std::invalid_argument("resume needs the state scale of the original run");
  if (start.u.size() != problem_.size() || start.tu.size() != problem_.size())
    throw std::invalid_argument(
        fmt::format("stored point has {} unknowns, the problem {}", start.u.size(), problem_.size()));
  set_norm(start.u, options_.state_scale);
  // a stored point located as a fold, an event, a branch point or a Hopf point is that point:
  // the restarted branch starts on its zero, which its first step does not cross again
  if (start.kind == PointKind::Fold || start.kind == PointKind::Event || start.kind == PointKind::BranchPoint ||
      start.kind == PointKind::Hopf)
    start_on_ = start.kind;
  start.kind = PointKind::Start;
  resumed_ = true;
  return trace(std::move(start), observer);
}

ContinuationResult Continuation::switch_branch(BranchPoint bp, int direction, BranchObserver& observer,
                                               const SwitchPrediction* prediction) {
  t_start_ = std::chrono::steady_clock::now();
  if (!(options_.state_scale > 0))
    throw std::invalid_argument("switch_branch needs the state scale of the original run");
  if (bp.u.size() != problem_.size() || bp.tu.size() != problem_.size())
    throw std::invalid_argument(
        fmt::format("stored point has {} unknowns, the problem {}", bp.u.size(), problem_.size()));
  set_norm(bp.u, options_.state_scale);
  start_on_.reset();
  adopted_ = false;
  resumed_ = false;
  BranchPoint start = bp;
  first_curvature_u_.resize(0);
  first_step_ = 0.0;
  Status st;
  if (prediction) {
    // the normal form's tangent, unit in the arclength norm: s = |t| epsilon, so d^2/ds^2 = (d^2/de^2) / |t|^2
    const double t = norm_.norm(prediction->tu, prediction->tl);
    if (!(t > 0) || !std::isfinite(t) || prediction->tu.size() != bp.u.size()) {
      st = {StatusCode::InvalidState, "the predicted tangent is zero"};
    } else {
      const double sign = direction >= 0 ? 1.0 : -1.0;
      start.tu = (sign / t) * prediction->tu;
      start.tlambda = sign * prediction->tl / t;
      if (prediction->second_u.size() == bp.u.size()) {
        first_curvature_u_ = prediction->second_u / (t * t);
        first_curvature_l_ = prediction->second_l / (t * t);
        // the tangent turns at the curvature's part normal to it per unit arclength: a first step
        // that turns it by at most 3/4 of the angle limit
        const double along = norm_.dot(first_curvature_u_, first_curvature_l_, start.tu, start.tlambda);
        const double kappa =
            norm_.norm(first_curvature_u_ - along * start.tu, first_curvature_l_ - along * start.tlambda);
        const double limit = 0.75 * options_.step.max_angle_degrees * std::numbers::pi / 180.0;
        if (kappa > 0 && std::isfinite(kappa)) first_step_ = std::min(options_.step.initial, limit / kappa);
      }
    }
  } else {
    st = branch_direction(ev_, lu_options_, norm_, bp, direction, start.tu, start.tlambda);
  }
  if (!st.is_ok()) {
    ContinuationResult r;
    r.code = StopCode::StartFailed;
    r.reason = "the branch could not start: no branch to switch to: " + st.describe();
    observer.on_finish(r.reason, bp);
    return r;
  }
  start.kind = PointKind::Start;
  start.label = "switched";
  start.s = 0.0;
  start.step = first_step_ > 0 ? first_step_ : options_.step.initial;
  first_step_ = 0.0;
  start.analysed = false;
  return trace(std::move(start), observer);
}

Status Continuation::begin(BranchPoint& start) {
  // the start: observables, the sign of det of the bordered matrix with its own tangent, and the
  // analysis (with that factorisation of J)
  const bool arclength = options_.method == ContinuationOptions::Method::Arclength;
  Status st = evaluate(start, false);
  // J's block factorisation made at this very point for the initial tangent (run) takes the
  // arclength row through its Schur complement: no second factorisation of the same matrix
  const bool factorised_here =
      arclength && kept_.block() && (kept_.made_at(start.u, start.lambda) || (adopted_ && kept_.reusable()));
  Vector F;
  if (st.is_ok()) st = arclength && !factorised_here ? ev_.jacobian(start.u) : ev_.residual(start.u, F);
  if (st.is_ok())
    start.residual = (arclength && !factorised_here ? ev_.residual_vector() : F).lpNorm<Eigen::Infinity>();
  const Constraint row = norm_.tangent_row(start.tu, start.tlambda);
  if (st.is_ok() && factorised_here && kept_.set_row(row).is_ok()) {
    kept_.record(ReuseEvent::Accepted);
    start.bordered_det_sign = kept_.determinant_sign();
  } else if (st.is_ok() && arclength) {
    st = ev_.parameter_derivative(start.u);
    if (st.is_ok()) {
      const Status sf = kept_.factorise_assembled(ev_, start.u, start.lambda, row);
      start.bordered_det_sign = sf.is_ok() ? kept_.determinant_sign() : 0;
    }
  }
  if (st.is_ok() && analysis_) analyse(start);
  return st;
}

ContinuationResult Continuation::trace(BranchPoint start, BranchObserver& observer) {
  result_ = ContinuationResult{};
  next_index_ = 0;
  observer.on_start(problem_.observable_names(), monitor_names_);
  const Status st = begin(start);
  if (!st.is_ok()) {
    result_.code = StopCode::StartFailed;
    result_.reason = "the branch could not start: the starting point cannot be evaluated: " + st.describe();
    return result_;
  }
  start.index = next_index_++;
  start.save = true;
  spectra_->restart(start, start.label == "switched");
  branch_points_.restart(start);
  // a branch restarted where it ended (on a stop it would go beyond) is at its end: one row
  if (std::optional<Finish> end = resumed_ ? end_at_start(start) : std::nullopt) {
    report(observer, start);
    return finish(end->code, end->reason, start, observer);
  }
  report(observer, start);

  BranchPoint cur = std::move(start);
  std::optional<BranchPoint> prev;
  bool landing_failed = false;  // the present step's landing was rejected: its retries do not land
  double ds = steps_.first(cur.step);
  int steps = 0;
  while (true) {
    if (stop_requested_.load()) return finish(StopCode::Interrupted, "interrupted by a signal", cur, observer);
    if (steps >= options_.stop.max_steps)
      return finish(StopCode::MaxSteps, fmt::format("max_steps = {} reached", options_.stop.max_steps), cur, observer);

    Step step = attempt(cur, prev ? &*prev : nullptr, ds, steps + 1, !landing_failed);
    if (!step.status.is_ok()) {
      landing_failed = step.land.has_value();
      ++result_.rejected;
      observer.on_rejected(step.point.lambda, ds, step.status);
      if (step.zero_at_start) continue;  // (the same step again, without landing)
      // a turn sharper than the angle limit even at short steps (a fold sharper than the
      // branch's scale) is passed at the step floor, not taken for the branch's end
      ds = step.turned ? steps_.after_turn(ds, step.angle) : steps_.after_failure(ds);
      if (steps_.below_floor(ds))
        return finish(StopCode::StepFloor,
                      fmt::format("step size fell below min_step = {} at {} = {:.10g}: {}", steps_.min(),
                                  options_.parameter, cur.lambda, step.status.describe()),
                      cur, observer);
      continue;
    }
    ++steps;
    landing_failed = false;
    BranchPoint& nxt = step.point;
    const double ds_next = steps_.after_accepted(ds, step.outcome);
    nxt.step = ds_next;
    std::vector<LocatedPoint> located = locate_on(cur, nxt, step, steps >= options_.stop.max_steps, observer);
    if (const std::optional<Finish> end = report_segment(cur, nxt, step, located, observer))
      return finish(end->code, end->reason, end->last, observer);
    prev = std::move(cur);
    cur = std::move(nxt);
    ds = ds_next;
  }
}

Continuation::Step Continuation::attempt(const BranchPoint& cur, const BranchPoint* prev, double ds, int step_number,
                                         bool landing_allowed) {
  const bool arclength = options_.method == ContinuationOptions::Method::Arclength;
  Step s;
  BranchPoint& nxt = s.point;
  Vector du;
  double dl = 0;
  predictor_.direction(cur, prev, du, dl);
  // the stop observable's zero, where no stop or bound comes before it (up to the zero, which may
  // lie beyond the planned step): the step's row is the function linearised at cur
  std::optional<ZeroLanding> zero = landing_allowed ? lander_.plan(cur, du, dl, ds) : std::nullopt;
  const double reach = zero ? std::max(1.0, zero->land.fraction) : 1.0;
  Prediction pr = predictor_.predict(cur, prev, du, dl, reach * ds, landing_allowed);
  if (zero && pr.land && pr.land->fraction * reach <= zero->land.fraction) zero.reset();
  if (zero) ZeroLander::predict(*zero, cur, du, dl, ds, pr);
  if (prev) predictor_.bend(cur, *prev, du, dl, pr);
  if (!prev && step_number == 1 && first_curvature_u_.size() == pr.u.size() && !pr.land && !zero) {
    // a switched branch's first step on the normal form's parabola
    pr.u += (0.5 * ds * ds) * first_curvature_u_;
    pr.lambda += 0.5 * ds * ds * first_curvature_l_;
  }
  s.land = pr.land;
  const bool landed = pr.land.has_value();
  nxt.u = std::move(pr.u);
  nxt.lambda = pr.lambda;
  const long factorisations = kept_.count();
  // a step that ends the branch on a bound makes its factorisation at its first correction: the sign
  // of det at the branch's end (branch points) comes from it, where a probe after the step would
  // factorise at the point besides
  if (landed && pr.land->end && arclength && options_.events.branch_points && options_.corrector.kept())
    kept_.record(ReuseEvent::SignWanted);
  const double floor = corrector_.residual_floor(cur.residual, prev ? prev->residual : 0.0);
  const CorrectorResult r = corrector_.correct(nxt.u, nxt.lambda, pr.constraint, Corrector::Kind::Step, floor);
  Status st = r.status;
  nxt.iterations = r.iterations;
  nxt.residual = r.residual;
  s.outcome.iterations = r.iterations;
  s.outcome.landed = landed;
  s.outcome.stale = options_.corrector.kept() && !r.refactored && r.iterations > steps_.target_iterations();
  if (st.is_ok() && zero) {
    // the linearised zero, settled by Newton on the function itself; where that does not settle,
    // the point reached is an ordinary row of the branch (a zero it stepped over is located)
    const Vector u_landed = nxt.u;
    const double lambda_landed = nxt.lambda;
    // the branch ends here: where the step made no factorisation, the sign of det for branch
    // points at its end would need one (a probe); Newton's first correction makes it instead
    if (options_.events.branch_points && kept_.count() == factorisations) kept_.record(ReuseEvent::SignWanted);
    const ZeroLander::Settled z = lander_.settle(*zero, cur, nxt, floor);
    const bool settled = z.settled;
    nxt.iterations += z.solves;
    if (settled && z.solves > 0) nxt.residual = z.residual;
    if (settled && std::abs(nxt.lambda - cur.lambda) <= options_.events.tolerance) {
      // the zero the step starts on (a function that is not continuous there: an event curve's
      // piece starts where the place just left is level with the followed one): an ordinary step
      s.zero_at_start = true;
      s.status = {StatusCode::NotConverged, "the landing found the zero the step starts on"};
      return s;
    }
    if (!settled) {
      nxt.u = u_landed;
      nxt.lambda = lambda_landed;
      s.land.reset();
    }
  }
  const bool analyse_now = spectra_->due(step_number, options_.stop.max_steps);
  // a point about to be analysed gets J's factorisation at itself (block elimination): the
  // tangent is then exact and the analysis solves with it instead of factorising J again
  const bool share = analyse_now && options_.corrector.block_elimination && analysis_->uses_j_factorisation();
  Constraint c = pr.constraint;
  if (st.is_ok() && landed) {
    // the tangent (and the sign of det of the bordered matrix, for branch points) under the
    // pseudo-arclength row, as at every other point of the branch
    c = norm_.arclength(cur, du, dl, ds);
    if (options_.corrector.kept() && kept_.block()) st = kept_.set_row(c);
  }
  // (without a kept factorisation the landed point's own one has the parameter row: a new one
  // under the pseudo-arclength row, or the sign of det flips with the sign of the parameter part
  // of the tangent and passes for a branch point)
  Tangent t;
  if (st.is_ok())
    st = tangents_.at_point(nxt, c, cur.tu, cur.tlambda, share || (landed && !options_.corrector.kept()), t);
  if (st.is_ok()) {
    nxt.tu = std::move(t.tu);
    nxt.tlambda = t.tl;
    nxt.det_sign = t.det_sign;
  } else {
    kept_.record(ReuseEvent::TangentFailed);
  }
  // a sharp turn of the tangent means the step skipped a feature of the branch or, in natural
  // continuation, jumped to another branch past a fold
  if (st.is_ok()) {
    const double angle = std::acos(std::clamp(norm_.dot(nxt.tu, nxt.tlambda, cur.tu, cur.tlambda), -1.0, 1.0));
    const double distance = norm_.distance(cur, nxt);
    const TurnVerdict turn = steps_.judge_turn(angle, ds, distance, arclength);
    if (turn == TurnVerdict::Far)
      st = {StatusCode::NotConverged,
            fmt::format("tangent turned by {:.1f} degrees at the step floor, to a point {:.3g} away",
                        angle * 180.0 / M_PI, distance)};
    else if (turn != TurnVerdict::Passed)
      st = {StatusCode::NotConverged, fmt::format("tangent turned by {:.1f} degrees", angle * 180.0 / M_PI)};
    s.turned = turn == TurnVerdict::Shorter;
    s.angle = angle;
  }
  if (st.is_ok()) st = evaluate(nxt, analyse_now);
  s.status = st;
  if (!st.is_ok()) return s;
  // the sign of det of the bordered matrix where J was factorised during this step
  s.sampled = arclength && kept_.count() > factorisations;
  nxt.bordered_det_sign = s.sampled ? kept_.determinant_sign() : 0;
  nxt.s = arclength && !landed ? cur.s + ds : cur.s + norm_.distance(cur, nxt);
  return s;
}

Status Continuation::evaluate(BranchPoint& p, bool analyse_point) {
  if (analyse_point && analysis_) analyse(p);
  const ScopeSeconds timed{ev_.timings().observables};
  Status st = ev_.set_parameter(p.lambda);
  if (st.is_ok()) st = problem_.observables(p.u, p.observables);
  if (st.is_ok()) st = problem_.monitors(p.u, p.monitors);
  if (!st.is_ok()) return st;
  for (double v : p.observables)
    if (!std::isfinite(v)) return {StatusCode::NotFinite, "an observable is not finite"};
  // the stop observable's distance to its thresholds is monitored like the problem's monitors
  if (stop_index_ >= 0) {
    if (std::isfinite(options_.stop.above)) p.monitors.push_back(p.observables[stop_index_] - options_.stop.above);
    if (std::isfinite(options_.stop.below)) p.monitors.push_back(p.observables[stop_index_] - options_.stop.below);
  }
  if (!monitors_usable(p.monitors, partial_)) return {StatusCode::NotFinite, "a monitor is not finite"};
  p.seconds = seconds_since(t_start_);
  return {};
}

void Continuation::analyse(BranchPoint& p) {
  // the analysis of a converged point; its failure is recorded, never a rejected step
  const auto t0 = std::chrono::steady_clock::now();
  Status st = ev_.set_parameter(p.lambda);
  PointAnalysisResult r;
  SparseLU* shared = st.is_ok() ? kept_.j_factorisation_at(p.u, p.lambda) : nullptr;
  const double solve_seconds0 = kept_.system().solve_seconds();
  const long solves0 = kept_.system().solves();
  if (st.is_ok()) st = analysis_->analyse(problem_, p.u, r, shared);
  // solves with the shared factorisation are the analysis's time, not the continuation's
  shared_solve_seconds_ += kept_.system().solve_seconds() - solve_seconds0;
  shared_solves_ += kept_.system().solves() - solves0;
  ev_.timings().analysis += seconds_since(t0);
  ++ev_.timings().analyses;
  p.analysed = true;
  p.analysis = std::move(r.columns);
  p.analysis.resize(analysis_->column_names().size(), NAN);
  p.count = st.is_ok() ? r.count : -1;
  p.analysis_width = r.width;
  p.locator = r.locator;
  p.critical_imag = r.critical_imag;
  p.critical_multiplicity = r.critical_multiplicity;
  p.critical_re = std::move(r.critical_re);
  p.critical_im = std::move(r.critical_im);
  if (!st.is_ok())
    analysis_note_ = "analysis failed: " + st.describe();
  else if (!r.note.empty())
    analysis_note_ = std::move(r.note);
}

void Continuation::report(BranchObserver& observer, BranchPoint& p) {
  const auto t0 = std::chrono::steady_clock::now();
  observer.on_point(p);
  ev_.timings().output += seconds_since(t0);
}

ContinuationResult Continuation::finish(StopCode code, std::string reason, const BranchPoint& last,
                                        BranchObserver& observer) {
  result_.code = code;
  result_.reason = std::move(reason);
  result_.points = next_index_;
  result_.factorisations = kept_.count();
  result_.tangent_iterations = tangents_.iterations();
  result_.renewal_cost = corrector_.renewal_cost();
  const SparseLU::Statistics& lu = kept_.system().lu().statistics();
  result_.nnz_lu = lu.nnz_lu;
  result_.lu_peak_bytes = lu.peak_memory_bytes;
  result_.lu_backend = lu.backend;
  ContinuationTimings t = ev_.timings();
  t.factorisation = kept_.system().factor_seconds();
  t.solve = kept_.system().solve_seconds() - shared_solve_seconds_;
  t.solves = kept_.system().solves() - shared_solves_;
  t.total = seconds_since(t_start_);
  result_.timings = t;
  result_.last = last;
  for (const std::string& n : unlocated_notes_.finish()) observer.on_note(n);
  observer.on_finish(result_.reason, last);
  return result_;
}

}  // namespace keller
