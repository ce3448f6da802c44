#include "runs/CurveStarts.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <complex>
#include <limits>

#include "continuation/curves/FoldCurveProblem.hpp"
#include "continuation/curves/HopfCurveProblem.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/NormalFormObserver.hpp"

namespace keller {

namespace {

// A curve's run options: the scene's, with an unfinished curve's scales.
ContinuationOptions curve_options(const TraceSettings& settings, const Unfinished* unfinished) {
  ContinuationOptions o = settings.continuation;
  if (unfinished) {
    o.state_scale = unfinished->state_scale;
    o.theta = unfinished->theta;
  }
  return o;
}

// Continuing `unfinished`: the curve's borders from its null vectors at its first state U (Vectors
// and Gain: FoldCurveProblem's or HopfCurveProblem's), refined at the row the unfinished curve
// continues from, at that row's value of the run's `parameter`.
template <class Vectors, class Gain, class Curve>
Status borders_at(Curve& curve, const Vector& U, Problem& problem, const std::string& parameter,
                  const Unfinished& unfinished) {
  Vectors v, w;
  Gain g{};
  Status st = curve.null_vectors(U, v, w, g);
  problem.parameters().set(parameter, unfinished.point.lambda);
  if (st.is_ok()) st = curve.set_borders(unfinished.point.u, v);
  return st;
}

// A fold or Hopf curve's start: from its corrected first state U or, continuing `unfinished`, from
// its last stored row; its borders moved to every point (Curve::BorderUpdate).
template <class Curve>
TraceStart bordered_start(std::unique_ptr<Curve> curve, Vector U, const TraceSettings& settings,
                          const Unfinished* unfinished) {
  TraceStart start;
  start.options = curve_options(settings, unfinished);
  if (unfinished) {
    start.begin = TraceStart::Begin::Point;
    start.point = unfinished->point;
    start.seed = unfinished->seed;
  } else {
    start.state = std::move(U);
  }
  start.borders = [c = curve.get()](BranchObserver& next) {
    return std::make_unique<typename Curve::BorderUpdate>(*c, next);
  };
  start.curve = std::move(curve);
  return start;
}

// The monitor of `problem` whose zero the stored row is: its event's label, or the stop
// observable's ("min_m1 < stop_below"); bad input where it has none.
std::string located_monitor_of(const Problem& problem, const StoredStart& from, const StoredPoint& stored) {
  const BranchPoint& event = stored.point;
  const std::string label = event.label.empty() ? stored.table.located_monitor(event.index) : event.label;
  std::string monitor;
  for (const std::string& m : problem.monitor_names())
    if (label == m || label.rfind(m + " ", 0) == 0) monitor = m;
  if (monitor.empty())
    throw CommandFailure::bad_input(fmt::format(
        "--from '{}': row {} ({}) is not the zero of a monitor of this problem ({})", from.file, event.index, label,
        problem.monitor_names().empty()
            ? std::string("it has none")
            : "its monitors: " + fmt::format("{}", fmt::join(problem.monitor_names(), ", "))));
  return monitor;
}

}  // namespace

TraceStart start_fold_curve(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                            const StoredPoint& stored, const Unfinished* unfinished) {
  const std::string& parameter = settings.continuation.parameter;
  use_stored_parameters(problem, stored);
  const BranchPoint& fold = stored.point;
  auto curve = std::make_unique<FoldCurveProblem>(problem, stored.table.parameter, settings.lu);
  Vector U = curve->state(fold.u, fold.lambda);
  const Status st = curve->start(U, fold.tu, settings.newton, settings.lu);
  if (!st.is_ok()) throw CommandFailure::numerical("the fold curve's first point failed", st);
  fmt::print("fold curve in ({}, {}) from the fold at row {} of {} ({} = {:.10g}, {} = {:.10g})\n", parameter,
             stored.table.parameter, fold.index, from.file, stored.table.parameter, U[U.size() - 1], parameter,
             problem.parameters().get(parameter));
  if (unfinished) {
    const Status b = borders_at<Vector, double>(*curve, U, problem, parameter, *unfinished);
    if (!b.is_ok()) throw CommandFailure::numerical("the unfinished fold curve cannot be continued", b);
    say_continuing("curve", *unfinished, parameter);
  }
  return bordered_start(std::move(curve), std::move(U), settings, unfinished);
}

TraceStart start_hopf_curve(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                            const StoredPoint& stored, const Unfinished* unfinished) {
  const std::string& parameter = settings.continuation.parameter;
  use_stored_parameters(problem, stored);
  const BranchPoint& hopf = stored.point;
  const std::optional<StoredMode> critical = read_branch_mode(from.file, hopf.index);
  if (!critical)
    throw CommandFailure::bad_input(
        fmt::format("--from '{}': row {} has no stored critical eigenvector (a Hopf point "
                    "of a branch traced with [stability] has one)",
                    from.file, hopf.index));
  auto curve = std::make_unique<HopfCurveProblem>(problem, stored.table.parameter, settings.lu);
  curve->set_lyapunov_coefficient(unit_mode_lyapunov_coefficient(settings.lu));
  Vector U = curve->state(hopf.u, hopf.lambda, std::abs(critical->sigma_im));
  // the mode of i omega, omega > 0: that of a stored -i omega conjugated
  const double side = critical->sigma_im < 0 ? -1.0 : 1.0;
  const ComplexVector mode = critical->re.cast<std::complex<double>>() + std::complex<double>(0.0, side) * critical->im;
  Status st = curve->start(U, mode, settings.newton, settings.lu);
  if (st.is_ok() && unfinished)
    st = borders_at<ComplexVector, std::complex<double>>(*curve, U, problem, parameter, *unfinished);
  if (!st.is_ok()) throw CommandFailure::numerical("the Hopf curve's first point failed", st);
  fmt::print(
      "Hopf curve in ({}, {}) from the Hopf point at row {} of {} ({} = {:.10g}, omega = {:.10g}, {} = {:.10g})\n",
      parameter, stored.table.parameter, hopf.index, from.file, stored.table.parameter, U[U.size() - 2],
      U[U.size() - 1], parameter, problem.parameters().get(parameter));
  if (unfinished) say_continuing("curve", *unfinished, parameter);
  return bordered_start(std::move(curve), std::move(U), settings, unfinished);
}

TraceStart start_event_curve(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                             const StoredPoint& stored, const Unfinished* unfinished) {
  const std::string& parameter = settings.continuation.parameter;
  use_stored_parameters(problem, stored);
  const BranchPoint& event = stored.point;
  const std::string monitor = located_monitor_of(problem, from, stored);
  TraceStart start;
  start.options = curve_options(settings, unfinished);
  if (!start.options.stop.observable.empty())
    fmt::print(
        "note: continuation.stop_observable ({}) is left aside: an event curve's pieces end where the "
        "minimum's place moves\n",
        start.options.stop.observable);
  // each piece of the curve ends where the minimum's place moves
  start.options.stop.observable = EventCurveProblem::kMargin;
  start.options.stop.below = 0.0;
  start.options.stop.above = std::numeric_limits<double>::infinity();
  auto curve = std::make_unique<EventCurveProblem>(problem, stored.table.parameter, monitor);
  Vector U = curve->state(event.u, event.lambda);
  if (unfinished) {
    problem.parameters().set(parameter, unfinished->point.lambda);
    U = unfinished->point.u;
  }
  auto tracer = std::make_unique<EventCurveTracer>(*curve);
  const Status st = tracer->start(U, settings.newton, settings.lu);
  if (!st.is_ok()) throw CommandFailure::numerical("the event curve's first point failed", st);
  fmt::print(
      "event curve of {} = 0 in ({}, {}) from row {} of {} ({} = {:.10g}, {} = {:.10g}), the minimum at place "
      "{}\n",
      monitor, parameter, stored.table.parameter, event.index, from.file, stored.table.parameter, U[U.size() - 1],
      parameter, problem.parameters().get(parameter), curve->place());
  if (unfinished) {
    say_continuing("curve", *unfinished, parameter);
    start.seed = unfinished->seed;
  }
  start.begin = TraceStart::Begin::EventCurve;
  start.state = std::move(U);
  start.event_curve = curve.get();
  start.event_tracer = std::move(tracer);
  start.curve = std::move(curve);
  return start;
}

}  // namespace keller
