// Continuation's location of what a step crossed (bounds, stops, monitors and thresholds, folds,
// turns, branch points, changes of the analysis's count) and the report of the located points and
// the step's own in order along the branch: the locate-and-report part of a step (the trace loop,
// the step and the start are in Continuation.cpp).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "continuation/Continuation.hpp"

namespace keller {

namespace {
// A critical eigenvalue whose imaginary part is below this (relative to 1 + |locator|) is real.
constexpr double kRealEigenvalue = 1e-8;
// A zero of a stop observable with smooth pieces is located on at most this many of them (each
// on the part of the segment before the last one's zero).
constexpr int kPieceLocations = 4;
// A point the engine located on the same step (a fold, a branch point by the determinant) within
// this many event tolerances of a located change of the count is the same point.
constexpr double kSameCrossing = 100.0;
}  // namespace

std::vector<LocatedPoint> Continuation::locate_on(BranchPoint& cur, BranchPoint& nxt, const Step& step, bool last_step,
                                                  BranchObserver& observer) {
  std::vector<LocatedPoint> located;
  locate_crossings(cur, nxt, step, located, observer);
  const bool ends =
      (step.land && step.land->end) ||
      std::any_of(located.begin(), located.end(), [](const LocatedPoint& l) { return l.end.has_value(); });
  locate_branch_points(cur, nxt, ends || last_step, located, observer);
  // a branch that ends on this step: its last stretch is checked too (analysis every N points)
  if (analysis_ && !nxt.analysed && ends) analyse(nxt);
  if (analysis_ && nxt.analysed) locate_stability_change(cur, nxt, located, observer);
  // what was detected but not located, unless the step located a fold or branch point after all (a
  // branch point the determinant's sign could not narrow down, located by the spectrum); the same
  // at successive steps (a determinant whose sign is rounding near a hard point) said once, then
  // counted
  std::vector<RepeatedNotes::Note> notes;
  for (const auto& [kind, label, note] : unlocated_) {
    const bool found_otherwise =
        (kind == PointKind::BranchPoint || kind == PointKind::Fold) &&
        std::any_of(located.begin(), located.end(), [&](const LocatedPoint& l) { return l.point.kind == kind; });
    if (!found_otherwise) notes.push_back({std::string(to_string(kind)) + " '" + label + "'", note});
  }
  for (const std::string& n : unlocated_notes_.step(notes, cur.index)) observer.on_note(n);
  unlocated_.clear();
  if (analysis_ && !analysis_note_.empty()) {
    // (the same note at successive points is said once)
    if (analysis_note_ != last_analysis_note_)
      observer.on_note(fmt::format("after row {}: {}", cur.index, analysis_note_));
    last_analysis_note_ = std::move(analysis_note_);
    analysis_note_.clear();
  } else if (nxt.analysed) {
    last_analysis_note_.clear();
  }
  if (start_on_ && cur.kind == PointKind::Start) {
    // the zero the start sits on, found again (its function's sign there is rounding)
    std::erase_if(located, [&](const LocatedPoint& l) {
      return l.point.kind == *start_on_ && std::abs(l.point.lambda - cur.lambda) <= options_.events.tolerance;
    });
  }
  start_on_.reset();
  order_located(located, nxt.s - cur.s, options_.events.tolerance);
  return located;
}

void Continuation::locate_crossings(const BranchPoint& cur, const BranchPoint& nxt, const Step& step,
                                    std::vector<LocatedPoint>& located, BranchObserver& observer) {
  const std::vector<Crossing> crossings =
      detect_crossings(cur, nxt, step.land, options_, monitor_names_, problem_.monitor_names().size(), turning_);
  std::vector<std::optional<BranchPoint>> zero_of(crossings.size());  // the points located for each
  for (size_t k = 0; k < crossings.size(); ++k) {
    const Crossing& c = crossings[k];
    std::optional<BranchPoint> p;
    std::string note;
    if (c.at_next) {
      p = nxt;
      // (the row of a step that landed on the zero; else the step's own row is reported too)
      if (!(step.land && step.land->monitor >= 0)) p->iterations = 0;
    } else if (c.same_as >= 0 && zero_of[static_cast<size_t>(c.same_as)]) {
      p = zero_of[static_cast<size_t>(c.same_as)];
    } else if (c.target.kind == EventTarget::Value) {
      p = locator_.locate_value(cur, nxt, c.target.value, note);
    } else {
      p = locate_zero(cur, nxt, c, note);
    }
    const size_t before = located.size();
    add_located(std::move(p), c.kind, c.label, c.end, cur, located, observer, note);
    if (located.size() > before) zero_of[k] = located.back().point;  // (analysed, if it was)
  }
}

std::optional<BranchPoint> Continuation::locate_zero(const BranchPoint& cur, const BranchPoint& nxt, const Crossing& c,
                                                     std::string& note) {
  const GradientFunction g = c.target.kind == EventTarget::Monitor ? lander_.gradient_of(c.target.monitor) : nullptr;
  const auto locate = [&](const BranchPoint& b, double ga, double gb) {
    std::optional<BranchPoint> p;
    if (g) p = locator_.locate_by_newton(cur, b, g, ga, gb, note);
    if (!p) p = locator_.locate_root(cur, b, c.target, ga, gb, note);
    return p;
  };
  const int observable = c.target.kind == EventTarget::Monitor ? lander_.observable_of(c.target.monitor) : -1;
  if (observable < 0 || !g || !ev_.has_pieces(observable)) return locate(nxt, c.ga, c.gb);
  // A stop observable that is the smallest of smooth pieces (the switch margin of an event curve,
  // the nearest of many places): where the smallest changes near its zero (a place far away
  // overtaking a level neighbour), Newton linearises the wrong piece and the secant creeps along
  // the level one. The piece smallest at the segment's end is smooth; where another piece is below
  // that one at the zero found on it, that one crossed first, before it.
  BranchPoint end = nxt;  // the segment cur -> end holds the first crossing
  double g_end = c.gb;
  for (int k = 0; k < kPieceLocations; ++k) {
    int piece = -1;
    if (!ev_.smallest_piece(observable, end.u, end.lambda, piece).is_ok() || piece < 0) break;
    double at_zero = 0.0;
    std::optional<BranchPoint> p = locate_on_piece(cur, end, c, piece, at_zero, note);
    if (!p || !evaluate(*p, false).is_ok()) break;
    const double value = c.target.of(*p);  // the observable itself
    if (value >= 0.0 || value >= at_zero || std::abs(p->lambda - end.lambda) <= options_.events.tolerance) return p;
    end = std::move(*p);
    g_end = value;
  }
  return locate(end, c.ga, g_end);
}

std::optional<BranchPoint> Continuation::locate_on_piece(const BranchPoint& cur, const BranchPoint& end,
                                                         const Crossing& c, int piece, double& at_zero,
                                                         std::string& note) {
  const GradientFunction g = lander_.piece_of(c.target.monitor, piece);
  const auto value = [&](const BranchPoint& q, double& v) {  // (the value alone: no difference step)
    Vector gu;
    double gl = 0.0;
    return g(q.u, q.lambda, 0.0, false, v, gu, gl);
  };
  double ga = 0.0, gb = 0.0;
  // (a piece that does not change sign on the segment: the observable itself, in locate_zero)
  if (!(value(cur, ga).is_ok() && value(end, gb).is_ok() && ga * gb < 0)) return std::nullopt;
  // the secant's trial points carry the piece's value as the threshold's monitor
  EventLocator on_piece(
      corrector_, tangents_, kept_, norm_, options_,
      [&](BranchPoint& p, bool analyse_point) {
        Status st = evaluate(p, analyse_point);
        double v = 0.0;
        if (st.is_ok()) st = value(p, v);
        if (st.is_ok()) p.monitors[static_cast<size_t>(c.target.monitor)] = v;
        return st;
      },
      [this]() { return analysis_note_; });
  std::optional<BranchPoint> p = on_piece.locate_by_newton(cur, end, g, ga, gb, note);
  if (!p) p = on_piece.locate_root(cur, end, c.target, ga, gb, note);
  if (p && !value(*p, at_zero).is_ok()) p.reset();
  return p;
}

int Continuation::probe_determinant(BranchPoint& p) {
  ++result_.probes;
  const Status st = kept_.factorise_at(ev_, p.u, p.lambda, norm_.tangent_row(p.tu, p.tlambda));
  if (!st.is_ok()) return 0;
  p.bordered_det_sign = kept_.determinant_sign();
  return p.bordered_det_sign;
}

void Continuation::keep_bracket_tangent(const BranchPoint& a, const BranchPoint& b, BranchPoint& p) const {
  // At a simple branch point the null space of [J F_p] is two-dimensional, so the tangent system
  // solved at the located point is singular there and its solution is dominated by J's null vector:
  // the new branch's direction, not the old one's. The old branch is smooth through the point, so
  // its tangent there is the bracketing points' tangents interpolated in arclength (what a restart
  // from the point and a switch, which takes the direction orthogonal to it, need).
  if (a.tu.size() != p.u.size() || b.tu.size() != p.u.size()) return;
  const double w = b.s != a.s ? std::clamp((p.s - a.s) / (b.s - a.s), 0.0, 1.0) : 0.5;
  Vector tu = (1.0 - w) * a.tu + w * b.tu;
  double tl = (1.0 - w) * a.tlambda + w * b.tlambda;
  const double n = norm_.norm(tu, tl);
  if (!(n > 0) || !std::isfinite(n)) return;
  p.tu = tu / n;
  p.tlambda = tl / n;
}

void Continuation::locate_branch_points(const BranchPoint& cur, BranchPoint& nxt, bool last,
                                        std::vector<LocatedPoint>& located, BranchObserver& observer) {
  if (options_.method != ContinuationOptions::Method::Arclength || !options_.events.branch_points) return;
  // the sign belongs to nxt itself where J was factorised there (or by Newton's last iteration),
  // else to an iterate of its step
  bool exact = kept_.made_at(nxt.u, nxt.lambda) || options_.corrector.method == CorrectorOptions::Method::Newton;
  if (branch_points_.needs_probe(nxt, last)) exact = probe_determinant(nxt) != 0;
  const auto pair = branch_points_.accepted(nxt, exact, [this](BranchPoint& q) { return probe_determinant(q); });
  if (!pair) return;
  std::string note;
  const Target target{EventTarget::BranchPoint, -1, 0.0};
  std::optional<BranchPoint> p = locator_.locate_root(pair->first, pair->second, target, pair->first.bordered_det_sign,
                                                      pair->second.bordered_det_sign, note);
  if (p) keep_bracket_tangent(pair->first, pair->second, *p);
  add_located(std::move(p), PointKind::BranchPoint, "det sign change", std::nullopt, cur, located, observer, note);
}

void Continuation::locate_stability_change(BranchPoint& cur, BranchPoint& nxt, std::vector<LocatedPoint>& located,
                                           BranchObserver& observer) {
  // a real eigenvalue through zero is a fold where the parameter turns, else a branch point; a
  // complex pair through the imaginary axis a Hopf point. Where the engine located the same fold
  // or branch point on this step itself, that point says so instead. A change of the count by more
  // than one crossing explains (two real eigenvalues, or pairs, crossing within one step) is
  // located crossing by crossing: each from the last one located to the end of the bracket.
  // The analysis widened at nxt (the unstable eigenvalues reached the edge of its set): the point
  // before came from the narrower set and may have missed eigenvalues that crossed and moved out of
  // it within the step before. It is analysed again, and a count it had wrong is said, loudly: that
  // change is not located.
  const auto analyse_point = [this](BranchPoint& q) { analyse(q); };
  // what the points located before this call are labelled (a re-location after widening undoes
  // what it appended to them)
  const size_t located_before = located.size();
  std::vector<std::string> labels_before;
  for (const LocatedPoint& l : located) labels_before.push_back(l.point.label);
  if (const auto r = spectra_->recount(cur, nxt, analyse_point)) {
    // (a fold or branch point the engine located before that row is one of the changes missed)
    const int change = std::abs(r->after - r->before);
    const int found = std::min(change, static_cast<int>(engine_located_before_analysed_.size()));
    std::string which = fmt::format("the change before row {} is not located", r->row);
    if (found > 0) {
      std::vector<std::string> at;
      for (int k = 0; k < found; ++k)
        at.push_back(fmt::format("{:.10g}", engine_located_before_analysed_[static_cast<size_t>(k)]));
      which = fmt::format("{} of its {} changes before row {} not located (the engine located {} at {} = {})",
                          change - found, change, r->row, found, options_.parameter, fmt::join(at, ", "));
    }
    observer.on_note(fmt::format(
        "row {} has {} {}, not {}: the analysis there computed too few eigenvalues to see them (it now computes "
        "{}); {} (a smaller continuation.max_step or a larger stability.count locates it)",
        r->row, r->after, analysis_->count_name(), r->before, nxt.analysis_width, which));
  }
  const auto change = spectra_->change_at(cur, nxt, analyse_point);
  if (!change) return;
  if (!change->bracketed) {
    observer.on_note(fmt::format("{} between rows {} and {} (not located: analysis every {} points)",
                                 change->description, change->from_row, next_index_, spectra_->every()));
    return;
  }
  const BranchPoint& b = *change->b;
  BranchPoint a = *change->a;
  const int direction = b.count > a.count ? 1 : -1;
  const Target target{EventTarget::StabilityChange, -1, 0.0};
  for (int crossings = 0; a.count != b.count && crossings < std::abs(b.count - change->a->count); ++crossings) {
    std::string note;
    std::optional<BranchPoint> p = locator_.locate_root(a, b, target, a.locator, b.locator, note);
    if (!p && !locator_.found_no_crossing() && change->this_step) {
      // the corrector failed near the crossing (J singular at a branch point): a fold or branch
      // point the engine located on this segment, and no crossing yet, is the crossing
      const auto found = std::find_if(located.begin(), located.end(), [&](const LocatedPoint& l) {
        return (l.point.kind == PointKind::BranchPoint || l.point.kind == PointKind::Fold) && l.point.s > a.s &&
               l.point.s <= b.s && l.point.label.find(analysis_->count_name()) == std::string::npos;
      });
      if (found != located.end()) {
        p = found->point;
        if (!p->analysed) analyse(*p);
      }
    }
    if (!p && locator_.found_no_crossing() && analysis_->widen()) {
      // what the analysis counts left its set within the step: computed wider (doubled, to a cap:
      // a few rounds at most), the step again
      analyse(nxt);
      locate_stability_change(cur, nxt, located, observer);
      return;
    }
    if (!p) {
      add_located(std::nullopt, PointKind::Event, fmt::format("{} {} -> {}", analysis_->count_name(), a.count, b.count),
                  std::nullopt, cur, located, observer, note);
      return;
    }
    const double scale = 1.0 + std::abs(p->locator);
    const bool complex = std::abs(p->critical_imag) > kRealEigenvalue * scale;
    // a multiple eigenvalue (two modes of a symmetric domain) crosses as many times as it is multiple
    const int crossed = (complex ? 2 : 1) * std::max(1, p->critical_multiplicity);
    if (direction * (a.count + direction * crossed - b.count) > 0 && analysis_->widen()) {
      // more crossed than the end of the bracket counts: its set missed modes that crossed and moved
      // out of it within the step; computed wider, the step again, its points located anew
      located.erase(located.begin() + static_cast<long>(located_before), located.end());
      for (size_t i = 0; i < located_before; ++i) located[i].point.label = labels_before[i];
      analyse(nxt);
      locate_stability_change(cur, nxt, located, observer);
      return;
    }
    const int after = std::clamp(a.count + direction * crossed, std::min(a.count, b.count), std::max(a.count, b.count));
    // the parameter turns on the bracket: the fold where this is its only crossing, else the
    // crossing where the engine located the fold
    const auto near_p = [&](const LocatedPoint& l) {
      return std::abs(l.point.lambda - p->lambda) <=
             kSameCrossing * options_.events.tolerance * (1.0 + std::abs(p->lambda));
    };
    const bool fold =
        turns(a.tlambda, b.tlambda, a, b) &&
        (after == b.count && crossings == 0 ? true
                                            : std::any_of(located.begin(), located.end(), [&](const LocatedPoint& l) {
                                                return l.point.kind == PointKind::Fold && near_p(l);
                                              }));
    const std::string crossing = fmt::format("{} {} -> {}", analysis_->count_name(), a.count, after);
    const PointKind kind = complex ? PointKind::Hopf : (fold ? PointKind::Fold : PointKind::BranchPoint);
    std::string label = complex ? fmt::format("omega = {:.8g}, {}", std::abs(p->critical_imag), crossing)
                                : fmt::format("eigenvalue crosses zero, {}", crossing);
    if (!change->this_step)
      label += fmt::format(" (bracketed by bisection between {} = {:.8g} and {:.8g})", options_.parameter,
                           change->a->lambda, b.lambda);
    // a branch point's own tangent is J's null vector (keep_bracket_tangent): the old branch's, from
    // the bracket, is what the next crossing's predictor, a restart and a switch need
    if (kind == PointKind::BranchPoint) keep_bracket_tangent(a, b, *p);
    // the rest of the change lies beyond this crossing: the next bracket starts on its far side
    // (its locator unknown there, so the search starts by bisection of the count)
    BranchPoint next = *p;
    next.count = after;
    next.locator = NAN;
    auto same = change->this_step
                    ? std::find_if(located.begin(), located.end(),
                                   [&](const LocatedPoint& l) { return l.point.kind == kind && near_p(l); })
                    : located.end();
    if (same != located.end())
      same->point.label += ", " + label;
    else
      add_located(std::move(p), kind, std::move(label), std::nullopt, cur, located, observer, note);
    a = std::move(next);
  }
}

void Continuation::add_located(std::optional<BranchPoint> p, PointKind kind, std::string label,
                               std::optional<StopCode> end, const BranchPoint& after,
                               std::vector<LocatedPoint>& located, BranchObserver& observer, std::string& note) {
  if (!p) {
    unlocated_.push_back(
        {kind, label,
         fmt::format("{} '{}' detected after row {} but not located: {}", to_string(kind), label, after.index, note)});
    return;
  }
  // located points get their spectrum with every point analysed (with every N > 1 they cost
  // one spectrum each, more than the branch's own: left out)
  if (analysis_ && !p->analysed && spectra_->every() == 1) analyse(*p);
  p->kind = kind;
  p->label = std::move(label);
  located.push_back({std::move(*p), end});
}

std::optional<Continuation::Finish> Continuation::end_at_start(BranchPoint& start) {
  const double lambda = start.lambda, tl = start.tlambda;
  const auto at_end = [&](StopCode code, const std::string& label, const std::string& where) {
    start.kind = PointKind::End;
    start.label = label;
    return Finish{code, fmt::format("the branch is at its end where it starts: {}", where), start};
  };
  const double tolerance = options_.events.tolerance;
  if (tl > 0 && lambda >= options_.stop.upper - tolerance)
    return at_end(StopCode::UpperBound, "upper",
                  fmt::format("the upper bound {} = {:.10g}", options_.parameter, options_.stop.upper));
  if (tl < 0 && lambda <= options_.stop.lower + tolerance)
    return at_end(StopCode::LowerBound, "lower",
                  fmt::format("the lower bound {} = {:.10g}", options_.parameter, options_.stop.lower));
  if (stop_index_ < 0) return std::nullopt;
  // the stop observable's rate along the tangent (a difference over a short arclength h): on or
  // beyond a threshold, going beyond it, the stop lies within the smallest step of the start
  constexpr double h = 1e-6;
  std::vector<double> ahead;
  Status st = ev_.set_parameter(lambda + h * tl);
  if (st.is_ok()) st = problem_.observables(start.u + h * start.tu, ahead);
  const Status back = ev_.set_parameter(lambda);
  if (!st.is_ok() || !back.is_ok() || ahead.size() <= static_cast<size_t>(stop_index_)) return std::nullopt;
  const double value = start.observables[static_cast<size_t>(stop_index_)];
  const double rate = (ahead[static_cast<size_t>(stop_index_)] - value) / h, reach = options_.step.min;
  const std::vector<std::string> names = options_.stop.threshold_monitor_names();
  auto where = [&](const std::string& name) {
    return fmt::format("{} at {} = {:.10g} ({} = {:.10g})", name, options_.parameter, lambda, options_.stop.observable,
                       value);
  };
  size_t k = 0;
  if (std::isfinite(options_.stop.above)) {
    if (rate > 0 && value - options_.stop.above + rate * reach >= 0)
      return at_end(StopCode::StopObservable, names[k], where(names[k]));
    ++k;
  }
  if (std::isfinite(options_.stop.below) && rate < 0 && value - options_.stop.below + rate * reach <= 0)
    return at_end(StopCode::StopObservable, names[k], where(names[k]));
  return std::nullopt;
}

std::optional<Continuation::Finish> Continuation::report_segment(const BranchPoint& cur, BranchPoint& nxt,
                                                                 const Step& step, std::vector<LocatedPoint>& located,
                                                                 BranchObserver& observer) {
  auto bound_reached = [&](const BranchPoint& p) {
    return fmt::format("reached the {} bound {} = {:.10g}", p.label, options_.parameter, p.lambda);
  };
  const double near = kSamePointFraction * std::abs(nxt.s - cur.s);
  bool next_reported = false;
  auto report_next = [&]() {
    next_reported = true;
    nxt.index = next_index_++;
    nxt.save = nxt.index % options_.save_every == 0;
    if (step.land) {
      nxt.kind = step.land->kind;
      nxt.label = step.land->label;
      nxt.save = true;
    }
    spectra_->reported(nxt);
    branch_points_.reported(nxt);
    if (nxt.analysed) {
      engine_located_before_analysed_ = std::move(engine_located_pending_);
      engine_located_pending_.clear();
    }
    report(observer, nxt);
  };
  for (LocatedPoint& l : located) {
    // an end found at a landed stop itself comes after the stop's row
    if (l.end && step.land && !step.land->end && std::abs(l.point.s - nxt.s) <= near) report_next();
    l.point.index = next_index_++;
    l.point.save = true;
    if (analysis_ && (l.point.kind == PointKind::BranchPoint || l.point.kind == PointKind::Fold) &&
        l.point.label.find(analysis_->count_name()) == std::string::npos)
      engine_located_pending_.push_back(l.point.lambda);
    report(observer, l.point);
    if (l.end) {
      const std::string why =
          *l.end == StopCode::StopObservable
              ? fmt::format("{} crossed at {} = {:.10g}", l.point.label, options_.parameter, l.point.lambda)
              : bound_reached(l.point);
      return Finish{*l.end, why, l.point};
    }
  }
  if (!next_reported) report_next();
  if (step.land && step.land->end) return Finish{*step.land->end, bound_reached(nxt), nxt};
  return std::nullopt;
}

}  // namespace keller
