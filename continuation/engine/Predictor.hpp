// The predictor of a continuation step: its direction (the unit tangent, or the secant through the
// last two points), and where the step goes: along the direction by the step size, or, where it
// would cross a stop or a bound, shortened to land on it (plan_landing, a pure planning function)
// and then corrected at that parameter value.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/BranchPoint.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/engine/StopCode.hpp"

namespace keller {

// A stop or a bound the next step lands on, or the zero of a stop observable's threshold.
struct Landing {
  double value = 0.0;     // the parameter value (a stop or a bound)
  double fraction = 0.0;  // of the planned step
  PointKind kind = PointKind::Requested;
  std::string label;
  std::optional<StopCode> end;  // set where landing there ends the branch (a bound, a stop observable)
  int monitor = -1;             // a zero: the monitor (index into BranchPoint::monitors) that vanishes there
};

// What plan_landing needs to know of the branch so far.
struct LandingQuery {
  double lambda = 0.0, s = 0.0, tlambda = 0.0;  // the current point
  bool has_previous = false;                    // with a tangent
  double previous_s = 0.0, previous_tlambda = 0.0;
  double step = 0.0;                                          // the planned step
  double max_step = std::numeric_limits<double>::infinity();  // the largest step allowed
  double direction = 0.0;                                     // the parameter part of the step's direction
};

// The nearest stop or bound the planned step would cross, or would fall short of by at most
// kLandingReach - 1 of its parameter change (the step is then stretched onto it, within the largest
// step: one step instead of a second, short one), if it may land on it: not within half
// the distance at which the parameter part of the tangent, extrapolated linearly from the last two
// points, vanishes (near a fold the correction at a fixed parameter is ill-posed and the value may
// lie beyond the fold), nor right after a fold. Bounds only when left from inside (the upper one
// upwards, the lower one downwards). Stops are labelled "<parameter> = <value>".
inline constexpr double kLandingReach = 1.25;
std::optional<Landing> plan_landing(const LandingQuery& q, const std::vector<double>& stops, double lower, double upper,
                                    const std::string& parameter);

// Where a step lands on the zero of a function along the branch, as a fraction of the planned
// step ds: g its value at the step's start, slope its derivative along the step's unit direction
// there. At the zero predicted linearly, where it lies ahead (g and slope of opposite signs),
// beyond kZeroNearest of the step (nearer, the step crosses it and it is located: a landing there
// would repeat a zero the start sits on, within rounding), within kZeroReach of the step and within
// max_step (further, the step would be longer than the step control allows).
std::optional<double> plan_zero_landing(double g, double slope, double ds, double max_step);
inline constexpr double kZeroNearest = 1e-3;
inline constexpr double kZeroReach = 1.25;

// Whether a prediction sigma beyond the current point follows the cubic through the previous point
// and this one (h apart, their tangents turn degrees): where the branch bends little between them
// (turn at most kCubicMaxTurn) and sigma lies ahead within kCubicReach of h. Where the tangent
// turns fast (27 degrees in one step where a measured branch leaves its start) the cubic
// overshoots, and beyond twice its base it extrapolates too far.
bool use_cubic(double turn_degrees, double sigma, double h);
inline constexpr double kCubicMaxTurn = 10.0;
inline constexpr double kCubicReach = 2.0;
// At a landing, the cubic's point on the step's row is taken within this fraction of the straight
// prediction's distance (beyond, Newton on the cubic found a root past a fold).
inline constexpr double kCubicLandingShift = 0.25;

struct Prediction {
  Vector u;
  double lambda = 0.0;
  Constraint constraint;        // the row the corrector solves under
  std::optional<Landing> land;  // the step lands on this value
};

class Predictor {
 public:
  Predictor(const ContinuationOptions& options, const ArclengthNorm& norm) : options_(options), norm_(norm) {}
  // The unit direction of the step from cur (prev: the point before it, if any).
  void direction(const BranchPoint& cur, const BranchPoint* prev, Vector& du, double& dl) const;
  // The prediction of a step of size ds from cur along (du, dl); landing_allowed: false after a
  // landing of this step failed (its retries are ordinary steps).
  Prediction predict(const BranchPoint& cur, const BranchPoint* prev, const Vector& du, double dl, double ds,
                     bool landing_allowed) const;
  // The cubic predictor (options.predictor Cubic, pseudo-arclength): the prediction p along (du, dl)
  // from cur moved onto the cubic through prev and cur with their tangents, where the cubic meets
  // p's row (the arclength row, a stop's value, a zero's linearised function), where use_cubic
  // allows; the row is kept. The corrector then starts O(ds^3) off the branch instead of O(ds^2).
  void bend(const BranchPoint& cur, const BranchPoint& prev, const Vector& du, double dl, Prediction& p) const;

 private:
  const ContinuationOptions& options_;
  const ArclengthNorm& norm_;
};

}  // namespace keller
