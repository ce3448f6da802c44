// A step that lands on the stop observable's threshold (continuation.land_on_zeros): the plan
// from the function and its gradient at the step's start (plan_zero_landing), the prediction
// under the function linearised there, and Newton on the function itself at the landed point
// (EventLocator::settle). Also the engine's access to the monitors' and thresholds' gradients.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "continuation/engine/Predictor.hpp"
#include "continuation/events/EventLocator.hpp"

namespace keller {

// The function with its value and gradient at the step's start, and where the step lands.
struct ZeroLanding {
  GradientFunction g;
  double h = 0.0;  // the difference step in lambda for its derivative
  double value = 0.0, gl = 0.0;
  Vector gu;
  Landing land;
};

class ZeroLander {
 public:
  ZeroLander(Evaluator& ev, EventLocator& locator, const ContinuationOptions& options)
      : ev_(ev), locator_(locator), options_(options) {}
  // The stop observable's index among the problem's observables (-1: none) and the names of
  // BranchPoint::monitors (the problem's monitors, problem_monitors of them, then the thresholds).
  void configure(int stop_index, int problem_monitors, std::vector<std::string> monitor_names);

  // The monitor (index into BranchPoint::monitors) with its gradient, where the problem offers
  // one (its zeros are then located by Newton, and a threshold's landed on); null where it does not.
  GradientFunction gradient_of(int monitor);
  // The observable a monitor is the threshold of (the stop observable's index), -1 for the
  // problem's own monitors.
  int observable_of(int monitor) const { return monitor >= problem_monitors_ ? stop_index_ : -1; }
  // One piece of the stop observable (ObservablePieces) minus the threshold `monitor` is of, with
  // its gradient.
  GradientFunction piece_of(int monitor, int piece);
  // The threshold's zero a step of size ds from cur along the unit direction (du, dl) lands on.
  std::optional<ZeroLanding> plan(const BranchPoint& cur, const Vector& du, double dl, double ds);
  // The step's prediction: at the predicted zero, under the function linearised at cur (which
  // must outlive the prediction's row).
  static void predict(const ZeroLanding& z, const BranchPoint& cur, const Vector& du, double dl, double ds,
                      Prediction& pr);
  struct Settled {
    bool settled = false;
    int solves = 0;         // the corrector's iterations
    double residual = NAN;  // of the last correction, where there was one
  };
  // Newton on the function itself from the landed point nxt (its moves predicted along cur's
  // tangent), with the corrector's residual floor.
  Settled settle(const ZeroLanding& z, const BranchPoint& cur, BranchPoint& nxt, double floor);

 private:
  // The stop threshold a monitor (one after the problem's) is the distance to.
  double threshold_of(int monitor) const;

  Evaluator& ev_;
  EventLocator& locator_;
  const ContinuationOptions& options_;
  int stop_index_ = -1;
  int problem_monitors_ = 0;
  std::vector<std::string> monitor_names_;
};

}  // namespace keller
