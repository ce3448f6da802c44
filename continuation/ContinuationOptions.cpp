#include "continuation/ContinuationOptions.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

namespace keller {

void ContinuationOptions::declare(SceneSchema& s) {
  s.section("continuation", "branch tracing (keller trace)");
  s.string("continuation.parameter", "", "named parameter to continue in (one of the problem's parameters)");
  s.string("continuation.method", "arclength", "pseudo-arclength (passes folds) or natural parameter steps",
           {"arclength", "natural"});
  s.string("continuation.predictor", "tangent", "predictor direction", {"tangent", "secant"});
  s.string("continuation.direction", "increase", "initial direction of the parameter", {"increase", "decrease"});
  s.real("continuation.lower", -INFINITY, "the branch ends where the parameter reaches this value (located exactly)");
  s.real("continuation.upper", INFINITY, "the branch ends where the parameter reaches this value (located exactly)");
  s.real_list("continuation.stops", {}, "parameter values where solutions are located and saved");
  s.boolean("continuation.land_on_values", true,
            "arclength: shorten a step whose predictor crosses a stop or a bound so that it lands on it (one "
            "correction instead of two, no step beyond a bound); false: locate such points after the step");
  s.real("continuation.initial_step", 0.05, "first step (arclength; natural: parameter units)", Range::positive());
  s.real("continuation.min_step", 1e-8, "step-size floor: below it the branch ends", Range::positive());
  s.real("continuation.max_step", 1.0, "largest step", Range::positive());
  s.integer("continuation.max_steps", 1000, "steps before the branch ends", Range::at_least(1));
  s.string("continuation.corrector", "newton",
           "newton: factorise every corrector iteration; chord: reuse the first factorisation of a step while the "
           "residual falls by chord_rate per iteration",
           {"newton", "chord"});
  s.string("continuation.bordered", "full",
           "bordered solves: factorise the whole extended matrix, or block elimination on J's factorisation "
           "(faster on large coupled problems; falls back to the whole matrix where J is singular)",
           {"full", "block"});
  s.real("continuation.chord_rate", 0.25, "chord corrector: refactorise when |F| falls by less than this factor",
         Range{0.0, 1.0, true, true});
  s.boolean("continuation.reuse_factorisation", false,
            "chord + block only: keep J's factorisation across steps, renewed when the chord rate fails in a step and, "
            "at a located point, only when the chord at its observed rate would need more than max_iterations; "
            "tangents by iteration on it (fewer than one factorisation per point on smooth branches)");
  s.real("continuation.renewal_cost", 0.0,
         "reuse_factorisation: a step's chord slower than chord_rate goes on while it needs at most this many more "
         "solves at its observed rate (a factorisation's cost in solves; 0: the rate rule alone)",
         Range::non_negative());
  s.integer("continuation.anderson_depth", 0,
            "chord corrector: Anderson acceleration over this many past updates on one factorisation (0: plain chord)",
            Range::between(0, 20));
  s.integer("continuation.target_iterations", 4, "corrector iterations aimed at by the step control",
            Range::at_least(1));
  s.integer("continuation.max_iterations", 10, "corrector iterations before a step is rejected", Range::at_least(1));
  s.real("continuation.growth", 1.5, "step growth factor after an easy step", Range::at_least(1));
  s.real("continuation.shrink", 0.5, "step reduction factor after a failed or hard step", Range{0.0, 1.0, true, true});
  s.real("continuation.max_angle_degrees", 20.0, "largest angle between successive tangents",
         Range{0.0, 180.0, true, false});
  s.real("continuation.theta", 0.5, "weight of the state (vs the parameter) in the arclength norm",
         Range{0.0, 1.0, true, true});
  s.real("continuation.state_scale", 0.0, "state scale in the arclength norm (0: RMS of the start)",
         Range::non_negative());
  s.real("continuation.event_tolerance", 1e-8, "events and folds are located to this tolerance in the parameter",
         Range::positive());
  s.integer("continuation.max_location_iterations", 60, "corrector solves allowed to locate one event",
            Range::at_least(1));
  s.boolean("continuation.detect_folds", true, "locate folds (turning points in the parameter)");
  s.boolean("continuation.detect_branch_points", true, "locate sign changes of det of the bordered Jacobian");
  s.integer("continuation.save_every", 10, "store the full solution of every N-th point", Range::at_least(1));
  s.string("continuation.stop_observable", "", "observable whose crossing of stop_above/stop_below ends the branch");
  s.real("continuation.stop_above", INFINITY, "end the branch where stop_observable rises through this value");
  s.real("continuation.stop_below", -INFINITY, "end the branch where stop_observable falls through this value");
}

ContinuationOptions ContinuationOptions::from_scene(const Scene& sc) {
  ContinuationOptions o;
  o.parameter = sc.string("continuation.parameter");
  if (o.parameter.empty()) throw sc.error("continuation.parameter", "a branch needs a parameter to continue in");
  o.method = sc.string("continuation.method") == "natural" ? Method::Natural : Method::Arclength;
  o.predictor = sc.string("continuation.predictor") == "secant" ? Predictor::Secant : Predictor::Tangent;
  o.corrector = sc.string("continuation.corrector") == "chord" ? Corrector::Chord : Corrector::Newton;
  o.chord_rate = sc.real("continuation.chord_rate");
  o.block_elimination = sc.string("continuation.bordered") == "block";
  o.reuse_factorisation = sc.boolean("continuation.reuse_factorisation");
  o.renewal_cost = sc.real("continuation.renewal_cost");
  o.anderson_depth = static_cast<int>(sc.integer("continuation.anderson_depth"));
  o.direction = sc.string("continuation.direction") == "decrease" ? -1 : +1;
  o.lower = sc.real("continuation.lower");
  o.upper = sc.real("continuation.upper");
  o.stops = sc.real_list("continuation.stops");
  o.land_on_values = sc.boolean("continuation.land_on_values");
  o.initial_step = sc.real("continuation.initial_step");
  o.min_step = sc.real("continuation.min_step");
  o.max_step = sc.real("continuation.max_step");
  o.max_steps = static_cast<int>(sc.integer("continuation.max_steps"));
  o.target_iterations = static_cast<int>(sc.integer("continuation.target_iterations"));
  o.max_iterations = static_cast<int>(sc.integer("continuation.max_iterations"));
  o.growth = sc.real("continuation.growth");
  o.shrink = sc.real("continuation.shrink");
  o.max_angle_degrees = sc.real("continuation.max_angle_degrees");
  o.theta = sc.real("continuation.theta");
  o.state_scale = sc.real("continuation.state_scale");
  o.event_tolerance = sc.real("continuation.event_tolerance");
  o.max_location_iterations = static_cast<int>(sc.integer("continuation.max_location_iterations"));
  o.detect_folds = sc.boolean("continuation.detect_folds");
  o.detect_branch_points = sc.boolean("continuation.detect_branch_points");
  o.save_every = static_cast<int>(sc.integer("continuation.save_every"));
  o.stop_observable = sc.string("continuation.stop_observable");
  o.stop_above = sc.real("continuation.stop_above");
  o.stop_below = sc.real("continuation.stop_below");
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    throw SceneError(fmt::format("{}: [continuation]: {}", sc.source(), e.what()));
  }
  return o;
}

void ContinuationOptions::validate() const {
  if (parameter.empty()) throw std::invalid_argument("no parameter to continue in");
  if (!(lower < upper)) throw std::invalid_argument(fmt::format("lower = {} must be below upper = {}", lower, upper));
  if (!(min_step <= initial_step && initial_step <= max_step))
    throw std::invalid_argument(
        fmt::format("need min_step <= initial_step <= max_step (got {}, {}, {})", min_step, initial_step, max_step));
  if (reuse_factorisation && !(corrector == Corrector::Chord && block_elimination))
    throw std::invalid_argument("reuse_factorisation needs corrector = \"chord\" and bordered = \"block\"");
  if (anderson_depth > 0 && corrector != Corrector::Chord)
    throw std::invalid_argument("anderson_depth needs corrector = \"chord\"");
  if (max_iterations < target_iterations)
    throw std::invalid_argument("max_iterations must be at least target_iterations");
  if (stop_observable.empty() && (std::isfinite(stop_above) || std::isfinite(stop_below)))
    throw std::invalid_argument("stop_above/stop_below need stop_observable");
  if (!stop_observable.empty() && !std::isfinite(stop_above) && !std::isfinite(stop_below))
    throw std::invalid_argument("stop_observable needs stop_above or stop_below");
}

}  // namespace keller
