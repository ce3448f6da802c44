// What a continuation step crossed, found from its two end points alone (pure functions): the
// parameter bounds and requested values, sign changes of the monitors (and of the stop
// observable's distance to its thresholds), and folds; and the order in which the located points
// are reported (along the branch, a zero found twice as a stop and as an event reported once).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "continuation/engine/AugmentedProblem.hpp"
#include "continuation/engine/BranchPoint.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/engine/Predictor.hpp"
#include "continuation/engine/StopCode.hpp"
#include "continuation/events/EventLocator.hpp"

namespace keller {

// A crossing to locate on the segment cur -> nxt.
struct Crossing {
  Target target;
  double ga = 0.0, gb = 0.0;  // the function at cur and nxt
  PointKind kind = PointKind::Event;
  std::string label;
  std::optional<StopCode> end;  // locating it ends the branch
  bool at_next = false;         // the zero is nxt itself (a landed stop where a monitor vanishes)
  int same_as = -1;             // the same function as an earlier crossing of this list: its zero
};

// Below this share of the tangent's largest part (its unknowns' and the parameter's), a part of the
// tangent is rounding: one that stays below it at both ends of a step does not turn there, whatever
// its signs (a curve along which a turning unknown stays constant, as the second parameter of a
// normal form's Hopf curve: its part of the tangent is 1e-20 of either sign). A real turn inside
// such a band would need a step below 1e-10 of the tangent's radius of curvature. The parts are
// the tangent's own, not weighted by the arclength norm: with weights far from 1 between the state
// and the parameter, the band is that much wider for the lighter one.
inline constexpr double kTangentRounding = 1e-10;

// Whether the part of the tangent g turns on the segment cur -> nxt (gc at cur, gn at nxt): a sign
// change with either end above kTangentRounding of its tangent.
bool turns(double gc, double gn, const BranchPoint& cur, const BranchPoint& nxt);

// Whether a point's monitor values can be used: each finite, or NaN where its index is one of the
// problem's partial monitors (AugmentedProblem::partial_monitors: undefined there). An infinite
// value, or NaN of any other monitor, is a failed evaluation.
bool monitors_usable(const std::vector<double>& values, const std::vector<int>& partial);

// The crossings of the segment cur -> nxt, in this order: bounds, requested values (except the
// value landed on), monitors (problem monitors are events, the stop thresholds ends), folds
// (arclength only), turns in the turning unknowns (arclength and folds only: events labelled
// "<name> max" or "<name> min"). monitor_names: the problem's monitors then the stop thresholds;
// problem_monitors: how many of them are the problem's.
std::vector<Crossing> detect_crossings(const BranchPoint& cur, const BranchPoint& nxt,
                                       const std::optional<Landing>& land, const ContinuationOptions& options,
                                       const std::vector<std::string>& monitor_names, size_t problem_monitors,
                                       const std::vector<AugmentedProblem::NamedUnknown>& turning_unknowns = {});

struct LocatedPoint {
  BranchPoint point;
  std::optional<StopCode> end;  // the branch ends here
};

// Sorts located points along the branch (by s) and drops an event that is also a located end of
// the stop observable (the same zero, within the event tolerance in the parameter and a thousandth
// of the segment along it); other kinds are always kept.
void order_located(std::vector<LocatedPoint>& located, double segment_length, double event_tolerance);

// Located points this close along the branch (a fraction of the segment) are the same point.
inline constexpr double kSamePointFraction = 1e-3;

}  // namespace keller
