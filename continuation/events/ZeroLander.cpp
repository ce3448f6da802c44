#include "continuation/events/ZeroLander.hpp"

#include <algorithm>
#include <cmath>

namespace keller {

void ZeroLander::configure(int stop_index, int problem_monitors, std::vector<std::string> monitor_names) {
  stop_index_ = stop_index;
  problem_monitors_ = problem_monitors;
  monitor_names_ = std::move(monitor_names);
}

GradientFunction ZeroLander::gradient_of(int monitor) {
  // the problem's monitors, then the stop observable's distance to stop_above, to stop_below
  if (monitor < problem_monitors_) return ev_.gradient_function(monitor, false, 0.0);
  return ev_.gradient_function(stop_index_, true, threshold_of(monitor));
}

GradientFunction ZeroLander::piece_of(int monitor, int piece) {
  return ev_.piece_function(stop_index_, piece, threshold_of(monitor));
}

double ZeroLander::threshold_of(int monitor) const {
  const bool above = monitor == problem_monitors_ && std::isfinite(options_.stop.above);
  return above ? options_.stop.above : options_.stop.below;
}

std::optional<ZeroLanding> ZeroLander::plan(const BranchPoint& cur, const Vector& du, double dl, double ds) {
  if (!options_.events.land_on_zeros || options_.method != ContinuationOptions::Method::Arclength || stop_index_ < 0)
    return std::nullopt;
  std::optional<ZeroLanding> best;
  for (size_t m = static_cast<size_t>(problem_monitors_); m < monitor_names_.size() && m < cur.monitors.size(); ++m) {
    ZeroLanding z;
    z.g = gradient_of(static_cast<int>(m));
    if (!z.g) return std::nullopt;
    // the difference step in lambda for the function's derivative: a small part of the step's
    z.h = 1e-4 * std::max(std::abs(ds * dl), 1e-8 * (1.0 + std::abs(cur.lambda)));
    if (!z.g(cur.u, cur.lambda, z.h, true, z.value, z.gu, z.gl).is_ok()) continue;
    const std::optional<double> fraction = plan_zero_landing(z.value, z.gu.dot(du) + z.gl * dl, ds, options_.step.max);
    if (!fraction || (best && best->land.fraction <= *fraction)) continue;
    z.land.fraction = *fraction;
    z.land.value = NAN;
    z.land.kind = PointKind::End;
    z.land.label = monitor_names_[m];
    z.land.end = StopCode::StopObservable;
    z.land.monitor = static_cast<int>(m);
    best = std::move(z);
  }
  return best;
}

void ZeroLander::predict(const ZeroLanding& z, const BranchPoint& cur, const Vector& du, double dl, double ds,
                         Prediction& pr) {
  const double at = z.land.fraction * ds;
  pr.u = cur.u + at * du;
  pr.lambda = cur.lambda + at * dl;
  pr.constraint = Constraint{};
  pr.constraint.cu = z.gu;
  pr.constraint.cl = z.gl;
  pr.constraint.u0 = &cur.u;
  pr.constraint.l0 = cur.lambda;
  pr.constraint.target = -z.value;
  pr.land = z.land;
}

ZeroLander::Settled ZeroLander::settle(const ZeroLanding& z, const BranchPoint& cur, BranchPoint& nxt, double floor) {
  Settled out;
  CorrectorResult last;
  Status st;
  out.settled =
      locator_.settle(
          nxt, z.g, z.h, [&](const BranchPoint&) -> const BranchPoint& { return cur; }, floor, out.solves, last, st) &&
      last.status.is_ok();
  if (out.solves > 0) out.residual = last.residual;
  return out;
}

}  // namespace keller
