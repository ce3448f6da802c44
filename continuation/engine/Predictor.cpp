#include "continuation/engine/Predictor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "continuation/engine/Hermite.hpp"

namespace keller {

namespace {
// A step lands on a value only within this fraction of the distance to the extrapolated fold.
constexpr double kFoldDistanceFraction = 0.5;
// Natural continuation: a direction with a smaller parameter part cannot be scaled to the
// parameter step (at a fold): the state is predicted unchanged.
constexpr double kNaturalMinDirection = 1e-12;
}  // namespace

std::optional<Landing> plan_landing(const LandingQuery& q, const std::vector<double>& stops, double lower, double upper,
                                    const std::string& parameter) {
  if (!(std::abs(q.direction) > 0)) return std::nullopt;
  double to_fold = std::numeric_limits<double>::infinity();
  if (q.has_previous && q.s > q.previous_s) {
    if (q.previous_tlambda * q.tlambda <= 0) return std::nullopt;
    const double slope = (q.tlambda - q.previous_tlambda) / (q.s - q.previous_s);
    if (slope * q.tlambda < 0) to_fold = -q.tlambda / slope;
  }
  const double predicted = q.lambda + q.step * q.direction;
  std::optional<Landing> best;
  // sense: +1 only crossing upwards (the upper bound, left from inside), -1 only downwards (the
  // lower bound), 0 either way (stops)
  auto consider = [&](double v, int sense, PointKind kind, std::string label, std::optional<StopCode> end) {
    if (!std::isfinite(v) || v == q.lambda || predicted == q.lambda) return;
    if (sense * (v - q.lambda) < 0) return;
    // ahead within the step, or a little beyond it (a step stretched onto the value instead of a
    // short one after it)
    const double fraction = (v - q.lambda) / (predicted - q.lambda);
    if (!(fraction > 0) || fraction > kLandingReach) return;
    if (fraction > 1 && fraction * q.step > q.max_step) return;
    if (fraction * q.step > kFoldDistanceFraction * to_fold) return;
    if (!best || fraction < best->fraction) best = Landing{v, fraction, kind, std::move(label), end};
  };
  consider(upper, +1, PointKind::End, "upper", StopCode::UpperBound);
  consider(lower, -1, PointKind::End, "lower", StopCode::LowerBound);
  for (double v : stops) consider(v, 0, PointKind::Requested, fmt::format("{} = {}", parameter, v), std::nullopt);
  return best;
}

bool use_cubic(double turn_degrees, double sigma, double h) {
  return turn_degrees <= kCubicMaxTurn && sigma > 0 && h > 0 && sigma <= kCubicReach * h;
}

std::optional<double> plan_zero_landing(double g, double slope, double ds, double max_step) {
  if (!(ds > 0) || !std::isfinite(g) || !std::isfinite(slope) || !(g * slope < 0)) return std::nullopt;
  const double at = -g / slope;  // the predicted distance to the zero along the direction
  if (!(at > kZeroNearest * ds) || !(at <= kZeroReach * ds) || !(at <= std::max(ds, max_step))) return std::nullopt;
  return at / ds;
}

void Predictor::direction(const BranchPoint& cur, const BranchPoint* prev, Vector& du, double& dl) const {
  du = cur.tu;
  dl = cur.tlambda;
  if (options_.predictor == ContinuationOptions::Predictor::Secant && prev) {
    du = cur.u - prev->u;
    dl = cur.lambda - prev->lambda;
    const double nrm = norm_.norm(du, dl);
    du /= nrm;
    dl /= nrm;
  }
}

Prediction Predictor::predict(const BranchPoint& cur, const BranchPoint* prev, const Vector& du, double dl, double ds,
                              bool landing_allowed) const {
  Prediction p;
  const bool arclength = options_.method == ContinuationOptions::Method::Arclength;
  if (landing_allowed && arclength && options_.events.land_on_values) {
    LandingQuery q;
    q.lambda = cur.lambda;
    q.s = cur.s;
    q.tlambda = cur.tlambda;
    q.has_previous = prev && prev->tu.size();
    if (q.has_previous) {
      q.previous_s = prev->s;
      q.previous_tlambda = prev->tlambda;
    }
    q.step = ds;
    q.max_step = options_.step.max;
    q.direction = dl;
    p.land = plan_landing(q, options_.events.stops, options_.stop.lower, options_.stop.upper, options_.parameter);
  }
  if (p.land) {
    // shortened to land on a stop or a bound: predicted along the same direction, corrected at
    // that parameter value
    p.lambda = p.land->value;
    p.u = cur.u + ((p.land->value - cur.lambda) / dl) * du;
    p.constraint = Constraint::parameter(p.land->value);
  } else if (arclength) {
    p.u = cur.u + ds * du;
    p.lambda = cur.lambda + ds * dl;
    p.constraint = norm_.arclength(cur, du, dl, ds);
  } else {
    const double dlam = options_.direction * ds;
    p.lambda = cur.lambda + dlam;
    p.u = std::abs(dl) > kNaturalMinDirection ? Vector(cur.u + (dlam / dl) * du) : cur.u;
    p.constraint = Constraint::parameter(p.lambda);
  }
  return p;
}

void Predictor::bend(const BranchPoint& cur, const BranchPoint& prev, const Vector& du, double dl,
                     Prediction& p) const {
  if (options_.predictor != ContinuationOptions::Predictor::Cubic ||
      options_.method != ContinuationOptions::Method::Arclength || prev.tu.size() != cur.tu.size())
    return;
  const double cosine = std::clamp(norm_.dot(prev.tu, prev.tlambda, cur.tu, cur.tlambda), -1.0, 1.0);
  const double turn = std::acos(cosine) * 180.0 / std::numbers::pi;
  // how far along: as far as the straight prediction went on the arclength row (the cubic meets that
  // row O(ds^3) from there); at a landing, where the cubic meets the step's row (a stop's or bound's
  // parameter value, a zero's linearised function), if that is near the straight prediction's (not a
  // root of the cubic beyond a fold)
  const double straight = norm_.dot(p.u - cur.u, p.lambda - cur.lambda, du, dl);
  std::optional<double> sigma = straight;
  if (p.land) {
    const Constraint& c = p.constraint;
    const BranchFunctional row = [&c](const Vector& v, double l, bool point) {
      if (point) return c.value(v, l);
      return (c.cu.size() ? c.cu.dot(v) : 0.0) + c.cl * l;
    };
    sigma = hermite_extrapolate_to(prev, cur, row, 0.0, straight);
    if (sigma && !(std::abs(*sigma - straight) <= kCubicLandingShift * straight)) return;
  }
  if (!sigma || !use_cubic(turn, *sigma, cur.s - prev.s)) return;
  const bool fixed = p.land && std::isfinite(p.land->value);  // a stop or bound: the parameter's value
  Vector u;
  double lambda = 0.0;
  if (!hermite_extrapolate(prev, cur, *sigma, u, lambda)) return;
  p.u = std::move(u);
  if (!fixed) p.lambda = lambda;
}

}  // namespace keller
