#include "continuation/curves/EventCurveProblem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace keller {

namespace {

// A switch's state starts the next piece as it is where the new equations' residual is within
// this factor of Newton's tolerance (its first step's corrector converges from there).
constexpr double kSwitchResidual = 1e3;
// A state this close to a switch's (relative, max norm) is the next piece's start: the run's
// correction of the start moves it by about 1e-11 of |U| (M2), the piece's steps by far more than
// 1e-8.
constexpr double kSwitchNeighbourhood = 1e-8;

int index_of(const std::vector<std::string>& names, const std::string& name, const std::string& what) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("event curve: unknown " + what + " '" + name + "' (" +
                                (known.empty() ? "none" : known) + ")");
  }
  return static_cast<int>(it - names.begin());
}

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

EventCurveProblem::EventCurveProblem(Problem& inner, const std::string& event_parameter, const std::string& monitor)
    : CurveProblem(inner, event_parameter, 1, "event curve"),
      monitor_(index_of(inner.monitor_names(), monitor, "monitor")) {}

Status EventCurveProblem::place_values(const Vector& U, std::vector<double>& values) {
  Status st = set_p1(U);
  if (!st.is_ok()) return st;
  st = places_of(inner_, monitor_, U.head(n_), values);
  if (!st.is_ok()) return st;
  if (place_ >= static_cast<int>(values.size()))
    throw std::logic_error("event curve: the monitor's places changed in number");
  return {};
}

Status EventCurveProblem::argmin(const Vector& U, int& place) {
  std::vector<double> v;
  Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  place = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
  return {};
}

Status EventCurveProblem::residual(const Vector& U, Vector& F) {
  std::vector<double> v;
  Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  Vector f;
  st = inner_.residual(U.head(n_), f);
  if (!st.is_ok()) return st;
  F.resize(n_ + 1);
  F.head(n_) = f;
  F[n_] = v[static_cast<size_t>(place_)];
  return {};
}

Status EventCurveProblem::place_parameter_derivative(int p, int place, const Vector& u, double& derivative) {
  Vector d;
  const Status st = parameter_difference(
      p,
      [&](Vector& value) {
        std::vector<double> v;
        const Status s = places_of(inner_, monitor_, u, v);
        if (s.is_ok()) value = Vector::Constant(1, v[static_cast<size_t>(place)]);
        return s;
      },
      d);
  if (st.is_ok()) derivative = d[0];
  return st;
}

Status EventCurveProblem::equations_parameter_derivative(int p, const Vector& U, Vector& d) {
  double mp = 0.0;
  Status st = set_p1(U);
  if (st.is_ok()) st = place_parameter_derivative(p, place_, U.head(n_), mp);
  d = Vector::Constant(1, mp);
  return st;
}

Status EventCurveProblem::bordered_jacobian(const Vector& U, Vector& F, BorderedJacobian& J) {
  if (J.border_size() != 1 || J.inner_size() != n_) J = blocks();
  Vector f;
  Status st = set_p1(U);
  if (st.is_ok()) st = inner_.jacobian(U.head(n_), f, J.K);
  if (!st.is_ok()) return st;
  return fill_border(U, f, F, J);
}

Status EventCurveProblem::border(const Vector& U, Vector& F, BorderedJacobian& J) {
  if (J.border_size() != 1 || J.inner_size() != n_) return bordered_jacobian(U, F, J);
  Vector f;
  Status st = set_p1(U);
  if (st.is_ok()) st = inner_.residual(U.head(n_), f);
  if (!st.is_ok()) return st;
  return fill_border(U, f, F, J);
}

Status EventCurveProblem::fill_border(const Vector& U, const Vector& f, Vector& F, BorderedJacobian& J) {
  std::vector<double> v;
  Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  F.resize(n_ + 1);
  F.head(n_) = f;
  F[n_] = v[static_cast<size_t>(place_)];
  Vector Fp1, gu;
  st = inner_.parameter_derivative(p1(), u, Fp1);
  if (st.is_ok()) st = place_gradient_of(inner_, monitor_, place_, u, gu);
  double gp1 = 0.0;
  if (st.is_ok()) st = place_parameter_derivative(p1(), place_, u, gp1);
  if (!st.is_ok()) return st;
  J.B.col(0) = Fp1;
  J.C.col(0) = gu;
  J.D(0, 0) = gp1;
  return {};
}

Status EventCurveProblem::observables(const Vector& U, std::vector<double>& values) {
  std::vector<double> v;
  Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  st = inner_.observables(U.head(n_), values);
  if (!st.is_ok()) return st;
  const int j = other_place(U, v);
  const double margin = j >= 0 ? v[static_cast<size_t>(j)] - v[static_cast<size_t>(place_)] : 1.0;
  values.push_back(U[n_]);
  values.push_back(place_);
  values.push_back(margin);
  return {};
}

int EventCurveProblem::other_place(const Vector& U, const std::vector<double>& v) const {
  // At the switch a piece starts from, the place it left is level with the followed one (not a new
  // crossing): the margin there is that of the other places, so that a third one overtaking within
  // the piece's first step is still a crossing.
  // (the piece's start is the switch's state or that state corrected by its run: within
  // kSwitchNeighbourhood of it; a step of the piece moves far more)
  const bool at_switch = switched_at_.size() == U.size() &&
                         (U - switched_at_).lpNorm<Eigen::Infinity>() <=
                             kSwitchNeighbourhood * std::max(1.0, switched_at_.lpNorm<Eigen::Infinity>());
  int other = -1;
  for (size_t j = 0; j < v.size(); ++j)
    if (static_cast<int>(j) != place_ && !(at_switch && static_cast<int>(j) == switched_from_) &&
        (other < 0 || v[j] < v[static_cast<size_t>(other)]))
      other = static_cast<int>(j);
  return other;
}

Status EventCurveProblem::observable_gradient(int observable, const Vector& U, Vector& gradient) {
  if (observable != margin_index()) return MonitorGradients::observable_gradient(observable, U, gradient);
  std::vector<double> v;
  const Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  const int j = other_place(U, v);
  if (j >= 0) return piece_gradient(observable, j, U, gradient);
  gradient = Vector::Zero(U.size());  // one place: the margin is constant
  return {};
}

void EventCurveProblem::check_margin(int observable) const {
  if (observable != margin_index())
    throw std::logic_error("event curve: observable " + std::to_string(observable) + " has no pieces");
}

void EventCurveProblem::check_piece(int observable, int piece) const {
  check_margin(observable);
  if (piece < 0 || piece == place_)
    throw std::logic_error("event curve: the switch margin has no piece " + std::to_string(piece) +
                           " (its pieces are the places other than the followed one, " + std::to_string(place_) + ")");
}

Status EventCurveProblem::smallest_piece(int observable, const Vector& U, int& piece) {
  check_margin(observable);
  std::vector<double> v;
  const Status st = place_values(U, v);
  if (st.is_ok()) piece = other_place(U, v);
  return st;
}

Status EventCurveProblem::piece_value(int observable, int piece, const Vector& U, double& value) {
  check_piece(observable, piece);
  std::vector<double> v;
  const Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  if (piece >= static_cast<int>(v.size()))
    throw std::out_of_range("event curve: the switch margin has no piece " + std::to_string(piece) + " (" +
                            std::to_string(v.size()) + " places)");
  value = v[static_cast<size_t>(piece)] - v[static_cast<size_t>(place_)];
  return {};
}

Status EventCurveProblem::piece_gradient(int observable, int piece, const Vector& U, Vector& gradient) {
  check_piece(observable, piece);
  Status st = set_p1(U);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  Vector gj, gk;
  double pj = 0.0, pk = 0.0;
  st = place_gradient_of(inner_, monitor_, piece, u, gj);
  if (st.is_ok()) st = place_gradient_of(inner_, monitor_, place_, u, gk);
  if (st.is_ok()) st = place_parameter_derivative(p1(), piece, u, pj);
  if (st.is_ok()) st = place_parameter_derivative(p1(), place_, u, pk);
  if (!st.is_ok()) return st;
  gradient = Vector::Zero(U.size());
  gradient.head(n_) = gj - gk;
  gradient[n_] = pj - pk;
  return {};
}

std::vector<std::string> EventCurveProblem::monitor_names() const {
  std::vector<std::string> names = inner_.monitor_names();
  names.erase(names.begin() + monitor_);
  return names;
}

Status EventCurveProblem::monitors(const Vector& U, std::vector<double>& values) {
  Status st = set_p1(U);
  if (!st.is_ok()) return st;
  st = inner_.monitors(U.head(n_), values);
  if (!st.is_ok()) return st;
  values.erase(values.begin() + monitor_);  // zero all along the curve: its sign is rounding
  return {};
}

std::string EventCurveProblem::summary() const {
  return fmt::format("event curve of {} = 0 (unknowns the state and {}) of {}", inner_.monitor_names()[monitor_],
                     p1_name(), inner_.summary());
}

Status EventCurveProblem::solve_kept(Vector& U, const NewtonOptions& newton, const SparseLUOptions& lu) {
  if (kept_.lu) {
    // at a located switch the new place's value is the old one's to the location's accuracy: U
    // nearly solves the new equations already, and Newton's first iteration would cost a Jacobian
    // and the factorisation's adoption for a correction the piece's first step makes anyway (the
    // switch is reported as the old piece's row, and the piece's start is not reported again)
    const auto t0 = std::chrono::steady_clock::now();
    Vector F;
    const Status st = residual(U, F);
    solve_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (st.is_ok() && F.lpNorm<Eigen::Infinity>() <= kSwitchResidual * newton.residual_tolerance * residual_scale())
      return {};
  }
  FixedParameterResult r = solve_here(U, newton, lu, kept_);
  kept_ = std::move(r.factorisation);
  solve_seconds_ += r.seconds;
  return r.status;
}

Status EventCurveProblem::start(Vector& U, const NewtonOptions& newton, SparseLUOptions lu) {
  Status st = argmin(U, place_);
  if (!st.is_ok()) return st;
  kept_ = {};
  st = solve_kept(U, newton, lu);
  if (!st.is_ok())
    return {StatusCode::NotConverged,
            "event curve: Newton from the located event did not converge (" + st.describe() + ")"};
  return {};
}

ContinuationResult EventCurveProblem::trace(ContinuationOptions o, const NewtonOptions& newton,
                                            const SparseLUOptions& lu, const Vector& U0, BranchObserver& observer,
                                            const std::function<void(Continuation*)>& each_run) {
  if (!o.stop.observable.empty() && o.stop.observable != kMargin)
    throw std::invalid_argument(
        "event curve: the stop observable is the switch margin (continuation.stop_observable "
        "must be unset)");
  o.stop.observable = kMargin;
  o.stop.below = 0.0;
  o.stop.above = std::numeric_limits<double>::infinity();
  switched_at_.resize(0);
  const double solves_before = solve_seconds_;
  Pieces pieces(observer);
  pieces.begin_piece(true, 0.0);
  Vector U = U0;
  ContinuationResult total;
  int steps_left = o.stop.max_steps;
  BranchPoint switched;  // the switch the present piece starts from (its tangent starts the piece's)
  for (bool first = true;; first = false) {
    Continuation run(*this, o, newton, lu);
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
    inner_.parameters().set(o.parameter, sw.lambda);
    int next = place_;
    {
      std::vector<double> v;
      const Status st = place_values(U, v);
      if (!st.is_ok()) break;
      double best = std::numeric_limits<double>::infinity();
      for (size_t j = 0; j < v.size(); ++j)
        if (static_cast<int>(j) != place_ && v[j] < best) best = v[j], next = static_cast<int>(j);
    }
    observer.on_note(fmt::format("after row {}: the minimum moves from place {} to place {} at {} = {:.10g}", sw.index,
                                 place_, next, o.parameter, sw.lambda));
    const int from = place_;
    place_ = next;
    if (!solve_kept(U, newton, lu).is_ok()) {
      total.reason = "event curve: no solution on the new place's piece at the switch";
      total.code = StopCode::StepFloor;
      break;
    }
    switched_at_ = U;
    switched_from_ = from;
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
