#include "continuation/engine/ContinuationOptions.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

void ContinuationOptions::declare(SceneSchema& s) {
  s.section("continuation", "branch tracing (keller trace); every key is documented in docs/continuation.md");
  // what is traced, and the norm
  s.string("continuation.parameter", "", "named parameter to continue in (one of the problem's parameters)");
  s.string("continuation.method", "arclength", "pseudo-arclength (passes folds) or natural parameter steps",
           {"arclength", "natural"});
  s.string("continuation.predictor", "cubic",
           "predictor: along the tangent, the secant, or the cubic through the last two points and their tangents",
           {"tangent", "secant", "cubic"});
  s.string("continuation.direction", "increase", "initial direction of the parameter", {"increase", "decrease"});
  s.string("continuation.switch_predictor", "normal-form",
           "how --switch starts the new branch: along the branch of the branch point's normal form, its first "
           "step on the normal form's parabola and sized by its curvature, or along J's null vector",
           {"normal-form", "null-vector"});
  s.real("continuation.theta", 0.5, "weight of the state (vs the parameter) in the arclength norm",
         Range{0.0, 1.0, true, true});
  s.real("continuation.state_scale", 0.0, "state scale in the arclength norm (0: RMS of the start)",
         Range::non_negative());
  s.integer("continuation.save_every", 10, "store the full solution of every N-th point", Range::at_least(1));
  // where it ends
  s.real("continuation.lower", -INFINITY, "the branch ends where the parameter reaches this value (located exactly)");
  s.real("continuation.upper", INFINITY, "the branch ends where the parameter reaches this value (located exactly)");
  s.integer("continuation.max_steps", 1000, "steps before the branch ends", Range::at_least(1));
  s.string("continuation.stop_observable", "", "observable whose crossing of stop_above/stop_below ends the branch");
  s.real("continuation.stop_above", INFINITY, "end the branch where stop_observable rises through this value");
  s.real("continuation.stop_below", -INFINITY, "end the branch where stop_observable falls through this value");
  // step control
  s.real("continuation.initial_step", 0.05, "first step (arclength; natural: parameter units)", Range::positive());
  s.real("continuation.min_step", 1e-8, "step-size floor: below it the branch ends", Range::positive());
  s.real("continuation.max_step", 1.0, "largest step", Range::positive());
  s.integer("continuation.target_iterations", 0,
            "step control: grow the step below this many corrector iterations, shrink above (0: the corrector's own, "
            "14 chord, 4 Newton)",
            Range::at_least(0));
  s.real("continuation.growth", 1.5, "step growth factor after a step below target_iterations", Range::at_least(1));
  s.real("continuation.slow_shrink", 0.7, "step factor after a step above target_iterations",
         Range{0.0, 1.0, true, false});
  s.real("continuation.shrink", 0.5, "step factor after a failed step", Range{0.0, 1.0, true, true});
  s.real("continuation.max_angle_degrees", 20.0, "largest angle between successive tangents",
         Range{0.0, 180.0, true, false});
  // the corrector
  s.string("continuation.corrector", "chord",
           "chord: J's factorisation kept while the residual falls fast enough (renewal_cost, chord_rate), "
           "Anderson-accelerated; newton: a Jacobian and its factorisation every iteration",
           {"newton", "chord"});
  s.string("continuation.bordered", "block",
           "bordered solves: block elimination on J's factorisation (falls back to the whole extended matrix where J "
           "is singular, as at a fold), or the whole extended matrix factorised",
           {"full", "block"});
  s.boolean("continuation.reuse_factorisation", true,
            "chord with block elimination: keep J's factorisation across steps, tangents by iteration on it (ignored "
            "with corrector = newton or bordered = full)");
  s.real("continuation.chord_rate", 0.25, "chord: a new factorisation when |F| falls by less than this factor",
         Range{0.0, 1.0, true, true});
  s.real("continuation.renewal_cost", 0.0,
         "chord: a slower chord goes on while it needs at most this many more iterations (what a factorisation "
         "costs in solves); 0: measured along the run (Jacobian and factorisation time over residual and solve time)",
         Range::non_negative());
  s.integer("continuation.anderson_depth", 5,
            "chord: Anderson acceleration over this many past updates on one factorisation (0: plain chord)",
            Range::between(0, 20));
  s.integer("continuation.max_iterations", 0,
            "corrector iterations before a step is rejected (0: the corrector's own, 30 chord, 10 Newton)",
            Range::at_least(0));
  // what is located
  s.real_list("continuation.stops", {}, "parameter values where solutions are located and saved");
  s.boolean("continuation.land_on_values", true,
            "arclength: shorten a step whose predictor crosses a stop or a bound so that it lands on it (one "
            "correction instead of two, no step beyond a bound), or stretch one that falls short of it by at most a "
            "quarter (one step instead of two); false: locate such points after the step");
  s.boolean("continuation.land_on_zeros", true,
            "arclength: a step whose linear prediction of the stop observable crosses its threshold (where the problem "
            "gives the observable's gradient) lands on that zero; false: locate it after the step");
  s.real("continuation.event_tolerance", 1e-8, "events and folds are located to this tolerance in the parameter",
         Range::positive());
  s.integer("continuation.max_location_iterations", 60, "corrector solves allowed to locate one event",
            Range::at_least(1));
  s.boolean("continuation.detect_folds", true, "locate folds (turning points in the parameter)");
  s.boolean("continuation.detect_branch_points", true,
            "locate sign changes of det of the bordered Jacobian (with a kept factorisation: from the factorisations "
            "the corrector makes, bracketed by factorising at points in between)");
}

std::vector<std::string> StopOptions::threshold_monitor_names() const {
  std::vector<std::string> names;
  if (observable.empty()) return names;
  if (std::isfinite(above)) names.push_back(observable + " > stop_above");
  if (std::isfinite(below)) names.push_back(observable + " < stop_below");
  return names;
}

ContinuationOptions ContinuationOptions::from_scene(const Scene& sc) {
  ContinuationOptions o;
  o.parameter = sc.string("continuation.parameter");
  if (o.parameter.empty()) throw sc.error("continuation.parameter", "a branch needs a parameter to continue in");
  o.method = sc.string("continuation.method") == "natural" ? Method::Natural : Method::Arclength;
  const std::string predictor = sc.string("continuation.predictor");
  o.predictor = predictor == "secant"    ? Predictor::Secant
                : predictor == "tangent" ? Predictor::Tangent
                                         : Predictor::Cubic;
  o.direction = sc.string("continuation.direction") == "decrease" ? -1 : +1;
  o.switch_normal_form = sc.string("continuation.switch_predictor") == "normal-form";
  o.theta = sc.real("continuation.theta");
  o.state_scale = sc.real("continuation.state_scale");
  o.save_every = static_cast<int>(sc.integer("continuation.save_every"));

  o.stop.lower = sc.real("continuation.lower");
  o.stop.upper = sc.real("continuation.upper");
  o.stop.max_steps = static_cast<int>(sc.integer("continuation.max_steps"));
  o.stop.observable = sc.string("continuation.stop_observable");
  o.stop.above = sc.real("continuation.stop_above");
  o.stop.below = sc.real("continuation.stop_below");

  o.step.initial = sc.real("continuation.initial_step");
  o.step.min = sc.real("continuation.min_step");
  o.step.max = sc.real("continuation.max_step");
  o.step.target_iterations = static_cast<int>(sc.integer("continuation.target_iterations"));
  o.step.growth = sc.real("continuation.growth");
  o.step.slow_shrink = sc.real("continuation.slow_shrink");
  o.step.shrink = sc.real("continuation.shrink");
  o.step.max_angle_degrees = sc.real("continuation.max_angle_degrees");

  o.corrector.method = sc.string("continuation.corrector") == "newton" ? CorrectorOptions::Method::Newton
                                                                       : CorrectorOptions::Method::Chord;
  o.corrector.block_elimination = sc.string("continuation.bordered") == "block";
  o.corrector.keep = sc.boolean("continuation.reuse_factorisation");
  o.corrector.chord_rate = sc.real("continuation.chord_rate");
  if (const double cost = sc.real("continuation.renewal_cost"); cost > 0) o.corrector.renewal_cost = cost;
  o.corrector.anderson_depth = static_cast<int>(sc.integer("continuation.anderson_depth"));
  o.corrector.max_iterations = static_cast<int>(sc.integer("continuation.max_iterations"));

  o.events.stops = sc.real_list("continuation.stops");
  o.events.land_on_values = sc.boolean("continuation.land_on_values");
  o.events.land_on_zeros = sc.boolean("continuation.land_on_zeros");
  o.events.tolerance = sc.real("continuation.event_tolerance");
  o.events.max_location_iterations = static_cast<int>(sc.integer("continuation.max_location_iterations"));
  o.events.folds = sc.boolean("continuation.detect_folds");
  o.events.branch_points = sc.boolean("continuation.detect_branch_points");
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    throw SceneError(fmt::format("{}: [continuation]: {}", sc.source(), e.what()));
  }
  return o;
}

void ContinuationOptions::validate() const {
  if (parameter.empty()) throw std::invalid_argument("no parameter to continue in");
  if (!(stop.lower < stop.upper))
    throw std::invalid_argument(fmt::format("lower = {} must be below upper = {}", stop.lower, stop.upper));
  if (!(step.min <= step.initial && step.initial <= step.max))
    throw std::invalid_argument(
        fmt::format("need min_step <= initial_step <= max_step (got {}, {}, {})", step.min, step.initial, step.max));
  if (max_iterations() < target_iterations())
    throw std::invalid_argument(fmt::format("max_iterations ({}) must be at least target_iterations ({})",
                                            max_iterations(), target_iterations()));
  if (stop.observable.empty() && (std::isfinite(stop.above) || std::isfinite(stop.below)))
    throw std::invalid_argument("stop_above/stop_below need stop_observable");
  if (!stop.observable.empty() && !std::isfinite(stop.above) && !std::isfinite(stop.below))
    throw std::invalid_argument("stop_observable needs stop_above or stop_below");
  if (!(step.shrink > 0 && step.shrink < 1)) throw std::invalid_argument("shrink must lie in (0, 1)");
  if (corrector.renewal_cost && !(*corrector.renewal_cost >= 0))
    throw std::invalid_argument("renewal_cost must be at least 0");
}

}  // namespace keller
