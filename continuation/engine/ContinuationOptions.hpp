// Options of the continuation engine, nested by the part that reads them: which parameter and
// norm (top level), step control (step), the corrector and its linear algebra (corrector), what is
// located on the branch (events) and where it ends (stop). Plain structs with defaults that are
// the fast, safe path; declare() lists the scene keys of [continuation] (flat keys, each with
// default, range and doc), from_scene() reads them back and validate() checks them.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/Scene.hpp"

namespace keller {

// Step control (StepController): step sizes in the arclength norm (natural method: parameter units).
struct StepOptions {
  double initial = 0.05;
  double min = 1e-8;  // the step-size floor: below it the branch ends, with the reason
  double max = 1.0;
  // Grow by `growth` after a step whose corrector needed fewer than target_iterations, shrink by
  // `slow_shrink` after one that needed more (0: the corrector's own target, see
  // CorrectorOptions::target()).
  int target_iterations = 0;
  double growth = 1.5;
  double slow_shrink = 0.7;
  double shrink = 0.5;              // factor on a failed step (divergence, NaN, a failure status, a sharp turn)
  double max_angle_degrees = 20.0;  // largest angle between successive unit tangents
};

// The corrector (Corrector), its renewal policy and the bordered solves (KeptFactorisation).
struct CorrectorOptions {
  // Newton: a Jacobian and its factorisation every iteration. Chord: J's factorisation is kept
  // (across steps, with `keep`) while the chord's residual falls fast enough (RenewalPolicy), its
  // iterations accelerated by Anderson mixing; a step outside Newton's region of contraction
  // (Deuflhard's monotonicity test) is halved at once.
  enum class Method { Newton, Chord };
  Method method = Method::Chord;
  // Bordered solves by block elimination on J's factorisation (falls back to the whole bordered
  // matrix where J is singular or nearly so, as at a fold itself); false: the whole bordered
  // matrix factorised each time.
  bool block_elimination = true;
  // Chord with block elimination: J's factorisation kept across steps (a tangent by iteration on
  // it, a new factorisation only when the renewal policy asks for one).
  bool keep = true;
  double chord_rate = 0.25;  // RenewalPolicy::chord_rate
  // RenewalPolicy::renewal_cost, in chord iterations (0: the rate rule alone); unset: measured along
  // the run, the mean time of a Jacobian with its factorisation over that of a residual with a solve.
  std::optional<double> renewal_cost;
  int anderson_depth = 5;  // chord: Anderson mixing over this many past updates (0: plain chord)
  int max_iterations = 0;  // corrector iterations before a step fails (0: max_iterations_default())
  // The corrector's defaults: a chord iteration costs a solve, a Newton one a factorisation.
  int target() const { return method == Method::Chord ? 14 : 4; }
  int max_iterations_default() const { return method == Method::Chord ? 30 : 10; }
  bool kept() const { return method == Method::Chord && block_elimination && keep; }
};

// What is located on the branch (EventLocator, EventDetector), and how precisely.
struct EventOptions {
  std::vector<double> stops;  // parameter values where solutions are located and saved
  // Pseudo-arclength: a step whose predictor would cross a stop or a bound is shortened to land
  // on it (one correction instead of a step past it and a located one; never a step beyond a
  // bound). Off: such points are located after the step that crosses them.
  bool land_on_values = true;
  // Pseudo-arclength: a step whose linear prediction of the stop observable (where the problem
  // gives its gradient) crosses its threshold lands on it: the step's row is the function
  // linearised, then Newton settles its zero (the step and its location in one). Off: the zero is
  // located after the step that crosses it.
  bool land_on_zeros = true;
  double tolerance = 1e-8;  // absolute, in the parameter
  int max_location_iterations = 60;
  bool folds = true;
  // Branch points (a sign change of det of the bordered Jacobian): where J is not factorised at
  // every point (a kept factorisation), from the factorisations the corrector makes, bracketed and
  // located by factorising at points in between (BranchPointMonitor).
  bool branch_points = true;
};

// Where the branch ends.
struct StopOptions {
  double lower = -std::numeric_limits<double>::infinity();  // the branch ends where the parameter
  double upper = std::numeric_limits<double>::infinity();   // reaches a bound (located exactly)
  int max_steps = 1000;
  std::string observable;  // ends where this observable crosses above / below
  double above = std::numeric_limits<double>::infinity();
  double below = -std::numeric_limits<double>::infinity();
  // The monitors a run adds for the stop observable's thresholds ("OBS > stop_above", "OBS <
  // stop_below", where set; none without a stop observable), after the problem's own.
  std::vector<std::string> threshold_monitor_names() const;
};

struct ContinuationOptions {
  enum class Method { Arclength, Natural };
  // Tangent: along the unit tangent; Secant: along the chord from the previous point; Cubic: along
  // the cubic through the previous point and this one with their tangents (Predictor::bend).
  enum class Predictor { Tangent, Secant, Cubic };

  std::string parameter;              // named parameter of the problem
  Method method = Method::Arclength;  // Keller's pseudo-arclength, or natural (parameter) steps
  Predictor predictor = Predictor::Cubic;
  int direction = +1;  // initial sign of the parameter change
  // --switch starts along the branch point's normal form (runs/NormalFormObserver), else J's null vector
  bool switch_normal_form = true;
  // Arclength norm |(du, dp)|^2 = theta |du|^2 / (n s^2) + (1 - theta) dp^2, s the state scale
  // (root mean square of the starting solution, or 1 if that is zero) so that states of any
  // magnitude weigh alike.
  double theta = 0.5;
  double state_scale = 0.0;  // 0: automatic
  int save_every = 10;       // full solutions of every N-th point (and of every located point)

  StepOptions step;
  CorrectorOptions corrector;
  EventOptions events;
  StopOptions stop;

  int target_iterations() const { return step.target_iterations > 0 ? step.target_iterations : corrector.target(); }
  int max_iterations() const {
    return corrector.max_iterations > 0 ? corrector.max_iterations : corrector.max_iterations_default();
  }

  static void declare(SceneSchema& schema);
  static ContinuationOptions from_scene(const Scene& scene);
  // Throws std::invalid_argument with a message naming the option.
  void validate() const;
};

}  // namespace keller
