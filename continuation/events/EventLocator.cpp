#include "continuation/events/EventLocator.hpp"

#include <fmt/format.h>

#include <cmath>

#include "continuation/engine/Hermite.hpp"

namespace keller {

namespace {
int sign_of(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }
// A located change of the count whose critical eigenvalue is within this fraction of its distance
// from the axis at the segment's ends has an eigenvalue at the axis (a crossing).
constexpr double kNearTheAxis = 1e-3;
// Illinois: where the same end of the bracket is kept twice, the other end's value is scaled by
// this (the secant then steps past the zero instead of creeping up on it).
constexpr double kIllinoisFactor = 0.5;
// Newton on a linearised function stops where its next move in lambda, predicted along a nearby
// tangent, is below this part of the event tolerance: quadratic convergence makes the last
// correction cheap, and the located value then is as good as the secant's settled trials.
constexpr double kNewtonSettled = 0.01;
// ... within this many corrections (it converges quadratically; where it does not, g is not
// smooth there: a minimum whose place changes, and the secant takes over).
constexpr int kNewtonCorrections = 6;
}  // namespace

const char* to_string(EventTarget t) {
  switch (t) {
    case EventTarget::Value: return "value";
    case EventTarget::Monitor: return "monitor";
    case EventTarget::Fold: return "fold";
    case EventTarget::BranchPoint: return "branch point";
    case EventTarget::StabilityChange: return "stability change";
    case EventTarget::Turn: return "turn";
  }
  return "?";
}

double Target::of(const BranchPoint& p) const {
  switch (kind) {
    case EventTarget::Value: return p.lambda - value;
    case EventTarget::Monitor: return p.monitors[static_cast<size_t>(monitor)];
    case EventTarget::Fold: return p.tlambda;
    case EventTarget::BranchPoint: return static_cast<double>(p.bordered_det_sign);
    case EventTarget::StabilityChange: return p.locator;
    case EventTarget::Turn: return p.tu[monitor];
  }
  return NAN;
}

EventLocator::EventLocator(Corrector& corrector, TangentSolver& tangents, KeptFactorisation& kept,
                           const ArclengthNorm& norm, const ContinuationOptions& options, Evaluate evaluate,
                           AnalysisNote analysis_note)
    : corrector_(corrector),
      tangents_(tangents),
      kept_(kept),
      norm_(norm),
      options_(options),
      evaluate_(std::move(evaluate)),
      analysis_note_(std::move(analysis_note)) {}

BranchPoint EventLocator::point_on_segment(const BranchPoint& a, const BranchPoint& b, double tau, Status& st,
                                           const BranchPoint& p0, const BranchPoint& p1, bool exact_tangent,
                                           bool analyse) {
  // where the target lies along the segment, in the coordinate the constraint fixes
  const bool arclength = options_.method == ContinuationOptions::Method::Arclength;
  auto coord = [&](const BranchPoint& p) {
    return arclength ? norm_.dot(p.u - a.u, p.lambda - a.lambda, a.tu, a.tlambda) : p.lambda;
  };
  const double target = arclength ? tau * coord(b) : a.lambda + tau * (b.lambda - a.lambda);
  // predictor: interpolation between the closest points known on the branch (the bracket)
  const double c0 = coord(p0), c1 = coord(p1);
  const double w = c1 != c0 ? (target - c0) / (c1 - c0) : tau;
  BranchPoint p;
  // the cubic Hermite interpolant of the bracket where it has the target coordinate; the chord
  // between them where it has none
  const BranchFunctional coordinate = [&](const Vector& u, double l, bool point) {
    if (!arclength) return l;
    return point ? norm_.dot(u - a.u, l - a.lambda, a.tu, a.tlambda) : norm_.dot(u, l, a.tu, a.tlambda);
  };
  double x = w;
  const bool cubic = hermite_point(p0, p1, coordinate, target, p.u, p.lambda, x);
  if (!cubic) {
    p.u = p0.u + w * (p1.u - p0.u);
    p.lambda = p0.lambda + w * (p1.lambda - p0.lambda);
  }
  const Constraint c = arclength ? norm_.arclength(a, a.tu, a.tlambda, target) : Constraint::parameter(target);
  const CorrectorResult r = corrector_.correct(p.u, p.lambda, c, Corrector::Kind::Located,
                                               corrector_.residual_floor(p0.residual, p1.residual));
  st = r.status;
  p.iterations = r.iterations;
  p.residual = r.residual;
  // The corrector's last factorisation is at its second-last iterate. Locating a fold (a zero of
  // the tangent's parameter part) or a sign change of the determinant needs them at the point
  // itself: one more factorisation there.
  // (by iteration from the tangent of the bracket's end nearer along the cubic)
  Tangent t;
  if (st.is_ok()) st = tangents_.at_point(p, c, a.tu, a.tlambda, exact_tangent, t, x < 0.5 ? &p0 : &p1);
  if (st.is_ok()) {
    p.tu = std::move(t.tu);
    p.tlambda = t.tl;
    p.det_sign = t.det_sign;
  }
  if (st.is_ok()) st = evaluate_(p, analyse);
  p.bordered_det_sign = kept_.determinant_sign();
  // where along the branch: on the cubic, the bracket's fraction x; else the coordinate's
  p.s = cubic ? p0.s + x * (p1.s - p0.s) : a.s + tau * (b.s - a.s);
  p.step = b.step;
  return p;
}

std::optional<BranchPoint> EventLocator::locate_value(const BranchPoint& a, const BranchPoint& b, double value,
                                                      std::string& note) {
  double tau = (value - a.lambda) / (b.lambda - a.lambda);
  BranchPoint p;
  // predictor: the cubic Hermite interpolant of the two points and their tangents (error O(h^4)
  // against O(h^2) for the chord between them), so that the corrector converges on the kept
  // factorisation instead of renewing it; the chord where the cubic does not reach the value
  double x = tau, lambda = value;
  const BranchFunctional parameter = [](const Vector&, double l, bool) { return l; };
  if (hermite_point(a, b, parameter, value, p.u, lambda, x))
    tau = x;
  else
    p.u = a.u + tau * (b.u - a.u);
  p.lambda = value;
  const Constraint c = Constraint::parameter(value);
  const CorrectorResult r =
      corrector_.correct(p.u, p.lambda, c, Corrector::Kind::Located, corrector_.residual_floor(a.residual, b.residual));
  Status st = r.status;
  p.iterations = r.iterations;
  p.residual = r.residual;
  Tangent t;
  if (st.is_ok()) st = tangents_.at_point(p, c, a.tu, a.tlambda, false, t);
  if (st.is_ok()) {
    p.tu = std::move(t.tu);
    p.tlambda = t.tl;
    p.det_sign = t.det_sign;
    st = evaluate_(p, false);
  }
  if (st.is_ok()) {
    p.lambda = value;  // exactly
    p.s = a.s + tau * (b.s - a.s);
    p.step = b.step;
    p.bordered_det_sign = 0;
    return p;
  }
  // at a fold the parameter cannot be fixed: fall back to root finding along the arclength
  note = "fixed-parameter corrector failed (" + st.describe() + "); ";
  Target root{EventTarget::Value, -1, value};
  return locate_root(a, b, root, a.lambda - value, b.lambda - value, note);
}

std::optional<BranchPoint> EventLocator::locate_root(const BranchPoint& a, const BranchPoint& b, const Target& target,
                                                     double ga, double gb, std::string& note) {
  const bool by_count = target.kind == EventTarget::StabilityChange;
  no_crossing_ = false;
  const int count_a = a.count;
  const bool sign_only = target.kind == EventTarget::BranchPoint;
  // functions that vanish where the branch turns in some sense: their bracket is measured along
  // the branch, not in the parameter alone
  const bool turning = target.kind == EventTarget::Fold || target.kind == EventTarget::Turn || sign_only || by_count;
  double ta = 0.0, tb = 1.0;
  BranchPoint pa = a, pb = b;
  int side = 0, solves = 0;
  double t_before = NAN;
  // a monitor's sign change through a pole (a test function 1 / (c^T J^-1 b) whose borders make the
  // denominator pass through zero) is no zero: there |g| grows on both sides as the bracket narrows,
  // past the larger of the ends' values (a zero next to an end whose |g| is rounding keeps |g| near
  // that end's, which a bound by the smaller end would take for a pole)
  const double larger_end = std::max(std::abs(ga), std::abs(gb));
  auto pole = [&](const BranchPoint& x, const BranchPoint& y) {
    const double gx = std::abs(target.of(x)), gy = std::abs(target.of(y));
    if (target.kind != EventTarget::Monitor || !std::isfinite(gx) || !std::isfinite(gy) ||
        !(std::min(gx, gy) > larger_end))
      return false;
    note += fmt::format("the monitor changes sign through a pole, not a zero (|g| grows from {:.3g} to {:.3g})",
                        larger_end, std::min(gx, gy));
    return true;
  };
  double last_lambda = NAN;
  for (int it = 0; it < options_.events.max_location_iterations; ++it) {
    const bool secant = !sign_only && (!by_count || (std::isfinite(ga) && std::isfinite(gb) && ga * gb < 0));
    double tc = secant ? tb - gb * (tb - ta) / (gb - ga) : 0.5 * (ta + tb);
    // a trial on or outside the bracket (rounding) falls back to bisection
    if (!(tc > ta && tc < tb)) tc = 0.5 * (ta + tb);
    Status st;
    const double lambda_before = it > 0 ? last_lambda : NAN;
    BranchPoint pc = point_on_segment(a, b, tc, st, pa, pb, target.needs_exact_tangent(), by_count);
    solves += pc.iterations;
    last_lambda = pc.lambda;
    if (!st.is_ok()) {
      note += "corrector failed while locating: " + st.describe();
      return std::nullopt;
    }
    const double gc = target.of(pc);
    // a partial monitor undefined inside the step (continuation/engine/AugmentedProblem.hpp): its
    // sign change there may be no zero at all, and none is sought
    if (target.kind == EventTarget::Monitor && !std::isfinite(gc)) {
      note += "the monitor is undefined inside the step (NaN): no zero sought";
      return std::nullopt;
    }
    if (by_count && pc.count < 0) {
      note += "analysis failed while locating: " + analysis_note_();
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
      if (side == -1 && !sign_only) gb *= kIllinoisFactor;
      side = -1;
    } else {
      tb = tc;
      gb = gc;
      pb = pc;
      if (side == +1 && !sign_only) ga *= kIllinoisFactor;
      side = +1;
    }
    double width = std::abs(pa.lambda - pb.lambda);
    if (turning) width = std::max(width, std::abs(pb.s - pa.s) * std::max(std::abs(pa.tlambda), std::abs(pb.tlambda)));
    // a zero of a monitor is also found once successive secant trials agree to the tolerance
    bool settled = !turning && std::abs(pc.lambda - lambda_before) <= options_.events.tolerance;
    // a count change located by secant on its locator: successive trials agree along the branch
    if (by_count && it > 0) settled = std::abs(tc - t_before) * std::abs(b.s - a.s) <= options_.events.tolerance;
    t_before = tc;
    // a change of the count narrowed to the tolerance (by bisection, or settled) where the eigenvalue
    // nearest the axis stays as far from it on both sides as at the segment's ends is no crossing:
    // an eigenvalue left or entered the set of those computed, or a different one is nearest on each
    // side (a set too small to count the same modes; a bracket start whose locator is not known is
    // the crossing, as the second one of a pair)
    const double far = std::max(std::isfinite(a.locator) ? std::abs(a.locator) : 0.0,
                                std::isfinite(b.locator) ? std::abs(b.locator) : 0.0);
    if (by_count && (settled || width <= options_.events.tolerance) && std::isfinite(pa.locator) &&
        std::isfinite(pb.locator) && std::min(std::abs(pa.locator), std::abs(pb.locator)) > kNearTheAxis * far) {
      no_crossing_ = true;
      note +=
          "the count changes there, but no eigenvalue crosses zero: one left or entered the set of those computed, "
          "or a different one is nearest the axis on each side (a larger stability.count keeps them)";
      return std::nullopt;
    }
    if (pole(pa, pb)) return std::nullopt;
    if (settled) {
      pc.iterations = solves;
      return pc;
    }
    if (width <= options_.events.tolerance) {
      const bool by_value = !turning || target.kind == EventTarget::Turn;
      BranchPoint& best = by_count   ? (std::abs(pa.locator) < std::abs(pb.locator) ? pa : pb)
                          : by_value ? (std::abs(target.of(pa)) < std::abs(target.of(pb)) ? pa : pb)
                                     : (std::abs(pa.tlambda) < std::abs(pb.tlambda) ? pa : pb);
      best.iterations = solves;
      return best;
    }
  }
  note += fmt::format("not located to {} in {} iterations", options_.events.tolerance,
                      options_.events.max_location_iterations);
  return std::nullopt;
}

std::optional<BranchPoint> EventLocator::locate_by_newton(const BranchPoint& a, const BranchPoint& b,
                                                          const GradientFunction& g, double ga, double gb,
                                                          std::string& note) {
  const bool arclength = options_.method == ContinuationOptions::Method::Arclength;
  const BranchFunctional coordinate = [&](const Vector& u, double l, bool point) {
    if (!arclength) return l;
    return point ? norm_.dot(u - a.u, l - a.lambda, a.tu, a.tlambda) : norm_.dot(u, l, a.tu, a.tlambda);
  };
  const auto coord = [&](const Vector& u, double l) { return coordinate(u, l, true); };
  const double length = coord(b.u, b.lambda);
  // the difference step in lambda for g's derivative: a small part of the segment's
  const double h = 1e-4 * std::max(std::abs(b.lambda - a.lambda), 1e-8 * (1.0 + std::abs(a.lambda)));
  // g's slope along the branch at a point with a tangent: d/dc of g(u(c), lambda(c)), c the
  // coordinate (the tangent is its derivative up to the coordinate's own scale)
  Vector gu;
  const auto slope = [&](const BranchPoint& q, double& value, double& ds) {
    double gl = 0.0;
    const Status st = g(q.u, q.lambda, h, true, value, gu, gl);
    if (!st.is_ok()) return st;
    const double dc = coordinate(q.tu, q.tlambda, false);
    ds = dc != 0.0 ? (gu.dot(q.tu) + gl * q.tlambda) / dc : NAN;
    return st;
  };
  // The prediction: the zero of the cubic Hermite interpolant of g along the segment (the
  // bracket's values and the slopes at both ends), the secant's where the slopes are not to be had.
  double xa = 0.0, xb = 0.0, value = 0.0;
  Status st = slope(a, value, xa);
  if (st.is_ok()) st = slope(b, value, xb);
  if (!st.is_ok()) {
    note += "the function's gradient failed: " + st.describe() + "; ";
    return std::nullopt;
  }
  double tau = ga / (ga - gb);
  if (std::isfinite(xa) && std::isfinite(xb) && length > 0) {
    const auto cubic = [&](double t) {
      const double h00 = (1 + 2 * t) * (1 - t) * (1 - t), h10 = t * (1 - t) * (1 - t), h01 = t * t * (3 - 2 * t),
                   h11 = t * t * (t - 1);
      return h00 * ga + h10 * length * xa + h01 * gb + h11 * length * xb;
    };
    double lo = 0.0, hi = 1.0, flo = ga;
    for (int it = 0; it < 60; ++it) {  // bisection on the cubic (scalar: cheap)
      const double mid = 0.5 * (lo + hi), fm = cubic(mid);
      if ((fm < 0) == (flo < 0))
        lo = mid, flo = fm;
      else
        hi = mid;
    }
    tau = 0.5 * (lo + hi);
  }
  const double floor = corrector_.residual_floor(a.residual, b.residual);
  // the move of each correction is predicted along the tangent of the segment's nearer end
  const auto nearer = [&](const BranchPoint& q) -> const BranchPoint& {
    return coord(q.u, q.lambda) < 0.5 * length ? a : b;
  };
  int solves = 0;
  CorrectorResult r;
  const auto refine = [&](BranchPoint& p) { return settle(p, g, h, nearer, floor, solves, r, st); };
  // From the cubic's zero corrected onto the branch under the arclength row (as a secant trial);
  // where that finds the zero a starts on again (a piece of an event curve starting on a switch,
  // where the place just left is level at a), from b; and the other way round.
  BranchPoint p;
  double along = NAN;
  bool settled = false;
  // A segment from the run's start begins from b: where the run starts on a zero of g's kind (an
  // event curve's piece starts on a switch, where the place just left is level with the followed
  // one), Newton from between the ends finds that zero first.
  const bool b_first = a.kind == PointKind::Start;
  for (int start = 0; start < 2 && !settled; ++start) {
    if ((start == 0) != b_first) {
      double x = tau;
      if (!hermite_point(a, b, coordinate, tau * length, p.u, p.lambda, x)) {
        p.u = a.u + tau * (b.u - a.u);
        p.lambda = a.lambda + tau * (b.lambda - a.lambda);
      }
      const Constraint onto =
          arclength ? norm_.arclength(a, a.tu, a.tlambda, tau * length) : Constraint::parameter(p.lambda);
      r = corrector_.correct(p.u, p.lambda, onto, Corrector::Kind::Located, floor);
      solves += r.iterations;
    } else {
      p = BranchPoint{};
      p.u = b.u;
      p.lambda = b.lambda;
      r = CorrectorResult{};
    }
    st = Status{};
    settled = refine(p) && r.status.is_ok();
    if (st.is_ok()) st = r.status;
    along = length != 0.0 ? coord(p.u, p.lambda) / length : NAN;
    if (!st.is_ok()) break;
    if (settled && std::abs(p.lambda - a.lambda) <= options_.events.tolerance) {
      note += "Newton on the linearised function found the zero the segment starts on; ";
      settled = false;
    }
  }
  p.iterations = solves;
  p.residual = r.residual;
  if (!st.is_ok() || !settled || !(along > 0.0 && along <= 1.0)) {
    note += !st.is_ok() ? "Newton on the linearised function failed (" + st.describe() + "); "
            : !settled  ? "Newton on the linearised function did not settle; "
                        : fmt::format("Newton on the linearised function left the segment (at {:.3g} of it); ", along);
    return std::nullopt;
  }
  const Constraint row =
      arclength ? norm_.arclength(a, a.tu, a.tlambda, along * length) : Constraint::parameter(p.lambda);
  Tangent t;
  st = tangents_.at_point(p, row, a.tu, a.tlambda, false, t, along < 0.5 ? &a : &b);
  if (st.is_ok()) {
    p.tu = std::move(t.tu);
    p.tlambda = t.tl;
    p.det_sign = t.det_sign;
    st = evaluate_(p, false);
  }
  if (!st.is_ok()) {
    note += "at the located point: " + st.describe() + "; ";
    return std::nullopt;
  }
  // the sign belongs to the arclength row only where the tangent factorised under it
  p.bordered_det_sign = t.factorised ? kept_.determinant_sign() : 0;
  p.s = a.s + along * (b.s - a.s);
  p.step = b.step;
  return p;
}

bool EventLocator::settle(BranchPoint& p, const GradientFunction& g, double h, const NearerPoint& nearer, double floor,
                          int& solves, CorrectorResult& r, Status& st) {
  // F = 0 under g linearised at the last point, gu . (u - u0) + gl (lambda - l0) = -g, while its
  // predicted move in lambda (along the nearer point's tangent, not p's own) exceeds
  // kNewtonSettled of the tolerance
  Vector gu;
  for (int it = 0; r.status.is_ok() && it <= kNewtonCorrections; ++it) {
    double gv = 0.0, gl = 0.0;
    st = g(p.u, p.lambda, h, true, gv, gu, gl);
    if (!st.is_ok()) return false;
    const BranchPoint& near = nearer(p);
    const double rate = gu.dot(near.tu) + gl * near.tlambda;  // g's change along that tangent
    if (rate == 0.0) {
      st = {StatusCode::SingularMatrix, "the function does not change along the branch"};
      return false;
    }
    const double move = -gv / rate;
    if (std::abs(move * near.tlambda) <= kNewtonSettled * options_.events.tolerance) return true;
    if (it == kNewtonCorrections) break;
    const Vector u0 = p.u;
    Constraint c;
    c.cu = gu;
    c.cl = gl;
    c.u0 = &u0;
    c.l0 = p.lambda;
    c.target = -gv;
    // predicted to where the row holds (the corrector then starts from that move's residual,
    // not from the converged point's rounding)
    p.u += move * near.tu;
    p.lambda += move * near.tlambda;
    r = corrector_.correct(p.u, p.lambda, c, Corrector::Kind::Located, floor);
    solves += r.iterations;
  }
  return false;
}

}  // namespace keller
