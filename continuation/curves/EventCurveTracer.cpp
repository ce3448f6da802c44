#include "continuation/curves/EventCurveTracer.hpp"

#include <fmt/format.h>

#include <chrono>
#include <limits>
#include <optional>
#include <stdexcept>

namespace keller {

namespace {

// A switch's state starts the next piece as it is where the new equations' residual is within
// this factor of Newton's tolerance (its first step's corrector converges from there).
constexpr double kSwitchResidual = 1e3;

// Passes the pieces of an event curve on as one branch: the start of a later piece is the switch
// already reported, rows and arclength run on, and the end of a piece at its switch is an event.
class Pieces final : public BranchObserver {
 public:
  explicit Pieces(BranchObserver& next) : next_(next) {}
  void begin_piece(bool first, double s0) {
    first_ = first;
    offset_ = first ? 0 : last_index_;
    s0_ = s0;
    t0_ = first ? 0.0 : last_seconds_;
    switch_.reset();
  }
  void on_start(const std::vector<std::string>& o, const std::vector<std::string>& m) override {
    if (first_) next_.on_start(o, m);
  }
  void on_point(const BranchPoint& q) override {
    if (!first_ && q.index == 0) return;
    BranchPoint p = q;
    p.index += offset_;
    p.s += s0_;
    p.seconds += t0_;
    last_seconds_ = p.seconds;
    if (p.kind == PointKind::End && p.label.rfind(EventCurveProblem::kMargin, 0) == 0) {
      p.kind = PointKind::Event;
      p.label = "switch";
      switch_ = p;
    }
    last_index_ = p.index;
    next_.on_point(p);
  }
  void on_rejected(double l, double s, const Status& w) override { next_.on_rejected(l, s, w); }
  void on_note(const std::string& m) override { next_.on_note(m); }
  void on_finish(const std::string& r, const BranchPoint& last) override {
    reason_ = r;
    last_ = last;
    last_.index += offset_;
    last_.s += s0_;
    last_.seconds += t0_;
  }
  void finish() { next_.on_finish(reason_, last_); }
  const std::optional<BranchPoint>& switched() const { return switch_; }
  const BranchPoint& last() const { return last_; }

 private:
  BranchObserver& next_;
  bool first_ = true;
  int offset_ = 0, last_index_ = 0;
  double s0_ = 0.0, t0_ = 0.0, last_seconds_ = 0.0;  // arclength and wall time of the earlier pieces
  std::optional<BranchPoint> switch_;
  std::string reason_;
  BranchPoint last_;
};

}  // namespace

Status EventCurveTracer::solve_kept(Vector& U, const NewtonOptions& newton, const SparseLUOptions& lu) {
  if (kept_.lu) {
    // at a located switch the new place's value is the old one's to the location's accuracy: U
    // nearly solves the new equations already, and Newton's first iteration would cost a Jacobian
    // and the factorisation's adoption for a correction the piece's first step makes anyway (the
    // switch is reported as the old piece's row, and the piece's start is not reported again)
    const auto t0 = std::chrono::steady_clock::now();
    Vector F;
    const Status st = curve_.residual(U, F);
    solve_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (st.is_ok() &&
        F.lpNorm<Eigen::Infinity>() <= kSwitchResidual * newton.residual_tolerance * curve_.residual_scale())
      return {};
  }
  FixedParameterResult r = curve_.solve_here(U, newton, lu, kept_);
  kept_ = std::move(r.factorisation);
  solve_seconds_ += r.seconds;
  return r.status;
}

Status EventCurveTracer::start(Vector& U, const NewtonOptions& newton, SparseLUOptions lu) {
  int place = 0;
  Status st = curve_.argmin(U, place);
  if (!st.is_ok()) return st;
  curve_.follow(place);
  kept_ = {};
  st = solve_kept(U, newton, lu);
  if (!st.is_ok())
    return {StatusCode::NotConverged,
            "event curve: Newton from the located event did not converge (" + st.describe() + ")"};
  return {};
}

ContinuationResult EventCurveTracer::trace(ContinuationOptions o, const NewtonOptions& newton,
                                           const SparseLUOptions& lu, const Vector& U0, BranchObserver& observer,
                                           const std::function<void(Continuation*)>& each_run) {
  if (!o.stop.observable.empty() && o.stop.observable != EventCurveProblem::kMargin)
    throw std::invalid_argument(
        "event curve: the stop observable is the switch margin (continuation.stop_observable "
        "must be unset)");
  o.stop.observable = EventCurveProblem::kMargin;
  o.stop.below = 0.0;
  o.stop.above = std::numeric_limits<double>::infinity();
  curve_.start_piece_at(Vector(), -1);
  const double solves_before = solve_seconds_;
  Pieces pieces(observer);
  pieces.begin_piece(true, 0.0);
  Vector U = U0;
  ContinuationResult total;
  int steps_left = o.stop.max_steps;
  BranchPoint switched;  // the switch the present piece starts from (its tangent starts the piece's)
  for (bool first = true;; first = false) {
    Continuation run(curve_, o, newton, lu);
    if (each_run) each_run(&run);
    const ContinuationResult r = run.run(U, pieces, std::move(kept_), first ? nullptr : &switched);
    if (each_run) each_run(nullptr);
    kept_ = run.factorisation();
    total.points += first ? r.points : r.points - 1;
    total.rejected += r.rejected;
    total.factorisations += r.factorisations;
    total.tangent_iterations += r.tangent_iterations;
    total.probes += r.probes;
    total.renewal_cost = r.renewal_cost;
    ContinuationTimings& t = total.timings;
    const ContinuationTimings& q = r.timings;
    t.jacobian += q.jacobian, t.parameter_derivative += q.parameter_derivative, t.residual += q.residual;
    t.factorisation += q.factorisation, t.solve += q.solve, t.observables += q.observables, t.output += q.output;
    t.total += q.total, t.analysis += q.analysis;
    t.jacobians += q.jacobians, t.parameter_derivatives += q.parameter_derivatives, t.residuals += q.residuals;
    t.solves += q.solves, t.analyses += q.analyses;
    total.code = r.code;
    total.reason = r.reason;
    total.last = pieces.last();
    steps_left -= r.points;
    if (r.code != StopCode::StopObservable || !pieces.switched() || steps_left <= 0) break;
    // the next piece: from the switch, following the place the minimum moved to
    const BranchPoint sw = *pieces.switched();
    switched = sw;
    U = sw.u;
    curve_.parameters().set(o.parameter, sw.lambda);
    const int from = curve_.place();
    int next = from;
    if (!curve_.next_place(U, next).is_ok()) break;
    observer.on_note(fmt::format("after row {}: the minimum moves from place {} to place {} at {} = {:.10g}", sw.index,
                                 from, next, o.parameter, sw.lambda));
    curve_.follow(next);
    if (!solve_kept(U, newton, lu).is_ok()) {
      total.reason = "event curve: no solution on the new place's piece at the switch";
      total.code = StopCode::StepFloor;
      break;
    }
    curve_.start_piece_at(U, from);
    o.state_scale = run.state_scale();
    o.direction = sw.tlambda >= 0 ? +1 : -1;
    o.step.initial = sw.step;  // the step the curve had reached, not a new start's
    o.stop.max_steps = steps_left;
    pieces.begin_piece(false, sw.s);
  }
  total.timings.total += solve_seconds_ - solves_before;  // the solves at the switches, between the pieces
  pieces.finish();
  return total;
}

}  // namespace keller
