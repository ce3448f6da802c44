#include "continuation/events/EventDetector.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace keller {

namespace {
double tangent_scale(const BranchPoint& p) {
  return std::max(p.tu.size() ? p.tu.cwiseAbs().maxCoeff() : 0.0, std::abs(p.tlambda));
}
}  // namespace

bool turns(double gc, double gn, const BranchPoint& cur, const BranchPoint& nxt) {
  return gc * gn < 0 &&
         std::max(std::abs(gc) / tangent_scale(cur), std::abs(gn) / tangent_scale(nxt)) > kTangentRounding;
}

bool monitors_usable(const std::vector<double>& values, const std::vector<int>& partial) {
  for (size_t k = 0; k < values.size(); ++k)
    if (!std::isfinite(values[k]) &&
        !(std::isnan(values[k]) && std::find(partial.begin(), partial.end(), static_cast<int>(k)) != partial.end()))
      return false;
  return true;
}

std::vector<Crossing> detect_crossings(const BranchPoint& cur, const BranchPoint& nxt,
                                       const std::optional<Landing>& land, const ContinuationOptions& o,
                                       const std::vector<std::string>& monitor_names, size_t problem_monitors,
                                       const std::vector<AugmentedProblem::NamedUnknown>& turning_unknowns) {
  std::vector<Crossing> out;
  auto value = [&](double v, PointKind kind, std::string label, std::optional<StopCode> end) {
    Crossing c;
    c.target = {EventTarget::Value, -1, v};
    c.ga = cur.lambda - v;
    c.gb = nxt.lambda - v;
    c.kind = kind;
    c.label = std::move(label);
    c.end = end;
    out.push_back(std::move(c));
  };
  if (cur.lambda <= o.stop.upper && nxt.lambda > o.stop.upper)
    value(o.stop.upper, PointKind::End, "upper", StopCode::UpperBound);
  if (cur.lambda >= o.stop.lower && nxt.lambda < o.stop.lower)
    value(o.stop.lower, PointKind::End, "lower", StopCode::LowerBound);
  for (double v : o.events.stops)
    if (!(land && v == land->value) &&
        ((cur.lambda - v) * (nxt.lambda - v) < 0 || (nxt.lambda == v && cur.lambda != v)))
      value(v, PointKind::Requested, fmt::format("{} = {}", o.parameter, v), std::nullopt);
  const size_t first_monitor = out.size();
  for (size_t k = 0; k < cur.monitors.size() && k < nxt.monitors.size(); ++k) {
    const double gc = cur.monitors[k], gn = nxt.monitors[k];
    // a zero exactly at nxt (a step that landed on a stop where a monitor vanishes) is this
    // step's, located at nxt itself; the next step starts on it and does not count it again. So
    // is the zero a step landed on (its value there is rounding, of either sign), and that of any
    // monitor that is the same function.
    const bool landed_zero = land && land->monitor >= 0 && static_cast<size_t>(land->monitor) < nxt.monitors.size() &&
                             gc != 0.0 && gc == cur.monitors[static_cast<size_t>(land->monitor)] &&
                             gn == nxt.monitors[static_cast<size_t>(land->monitor)];
    const bool at_next = (gn == 0.0 && gc != 0.0 && std::isfinite(gc)) || landed_zero;
    if (!(gc * gn < 0) && !at_next) continue;
    const bool stop = k >= problem_monitors;
    Crossing c;
    c.target = {EventTarget::Monitor, static_cast<int>(k), 0.0};
    c.ga = gc;
    c.gb = gn;
    c.kind = stop ? PointKind::End : PointKind::Event;
    c.label = k < monitor_names.size() ? monitor_names[k] : fmt::format("monitor {}", k);
    if (stop) c.end = StopCode::StopObservable;
    c.at_next = at_next;
    // the same function as a monitor before it on this step (a stop observable on a problem
    // monitor with threshold 0): the same zero, not a second search
    for (size_t j = first_monitor; j < out.size() && c.same_as < 0; ++j)
      if (cur.monitors[static_cast<size_t>(out[j].target.monitor)] == gc &&
          nxt.monitors[static_cast<size_t>(out[j].target.monitor)] == gn)
        c.same_as = static_cast<int>(j);
    out.push_back(std::move(c));
  }
  if (o.method == ContinuationOptions::Method::Arclength && o.events.folds &&
      turns(cur.tlambda, nxt.tlambda, cur, nxt)) {
    Crossing c;
    c.target = {EventTarget::Fold, -1, 0.0};
    c.ga = cur.tlambda;
    c.gb = nxt.tlambda;
    c.kind = PointKind::Fold;
    c.label = cur.tlambda > 0 ? "max" : "min";
    out.push_back(std::move(c));
  }
  if (o.method == ContinuationOptions::Method::Arclength && o.events.folds)
    for (const AugmentedProblem::NamedUnknown& t : turning_unknowns) {
      const double gc = cur.tu[t.index], gn = nxt.tu[t.index];
      if (!turns(gc, gn, cur, nxt)) continue;
      Crossing c;
      c.target = {EventTarget::Turn, t.index, 0.0};
      c.ga = gc;
      c.gb = gn;
      c.kind = PointKind::Event;
      c.label = t.name + (gc > 0 ? " max" : " min");
      out.push_back(std::move(c));
    }
  return out;
}

void order_located(std::vector<LocatedPoint>& located, double segment_length, double event_tolerance) {
  std::stable_sort(located.begin(), located.end(),
                   [](const LocatedPoint& x, const LocatedPoint& y) { return x.point.s < y.point.s; });
  const double near = kSamePointFraction * std::abs(segment_length);
  auto same_as_an_end = [&](const LocatedPoint& l) {
    return l.point.kind == PointKind::Event && std::any_of(located.begin(), located.end(), [&](const LocatedPoint& t) {
             return t.end == StopCode::StopObservable && std::abs(t.point.lambda - l.point.lambda) <= event_tolerance &&
                    std::abs(t.point.s - l.point.s) <= near;
           });
  };
  std::vector<bool> drop(located.size());
  for (size_t i = 0; i < located.size(); ++i) drop[i] = same_as_an_end(located[i]);
  std::vector<LocatedPoint> kept;
  for (size_t i = 0; i < located.size(); ++i)
    if (!drop[i]) kept.push_back(std::move(located[i]));
  located = std::move(kept);
}

}  // namespace keller
