#include "continuation/orbits/OrbitContinuation.hpp"

namespace keller {

void OrbitContinuationOptions::declare(SceneSchema& s) {
  const OrbitContinuationOptions d;
  s.section("orbit", "periodic orbits (keller trace --orbit); every key in docs/periodic_orbits.md");
  s.string("orbit.method", "sdirk4",
           "the integrator of the shooting map: sdirk4 (order 4) or bdf2 (evolve's default, order 2)",
           {"sdirk4", "bdf2"});
  s.real("orbit.relative_tolerance", 1e-6, "the local error per step of the grid's adaptive run (as evolve's)",
         Range{0.0, 1.0, true, true});
  s.real("orbit.absolute_tolerance", 1e-10, "the absolute part of its weights (below the orbit's amplitude)",
         Range::positive());
  s.real("orbit.tolerance", d.corrector.tolerance,
         "Newton's tolerance: |Phi(u0) - u0|_inf and the iterate's error (the last update, or the next one estimated "
         "from the residuals' contraction), relative to max(|u0|_inf, 1)",
         Range::positive());
  s.integer("orbit.multipliers", d.multipliers, "Floquet multipliers per orbit, of largest magnitude (0: none)",
            Range{0.0, 200.0, false, false});
  s.real("orbit.start_distance", d.start_distance,
         "the first orbit's distance from the Hopf point in the parameter (0: 1e-2 max(|lambda_H|, 1))",
         Range::non_negative());
  s.integer("orbit.frames", d.frames, "frames of `keller export --orbit` over a period, where --frames is not given",
            Range::at_least(2));
  // retired: the branch files of an earlier keller hold it in their stored scenes, which must still load
  s.integer("orbit.save_every", 1, "no effect (retired; kept so that the scenes stored in earlier orbit branches load)",
            Range::at_least(1));
}

OrbitContinuationOptions OrbitContinuationOptions::from_scene(const Scene& sc, const ContinuationOptions& c) {
  OrbitContinuationOptions o;
  o.time.method = sc.string("orbit.method") == "bdf2" ? TimeOptions::Method::Bdf2 : TimeOptions::Method::Sdirk4;
  o.time.relative_tolerance = sc.real("orbit.relative_tolerance");
  o.time.absolute_tolerance = sc.real("orbit.absolute_tolerance");
  o.corrector.tolerance = sc.real("orbit.tolerance");
  o.multipliers = static_cast<int>(sc.integer("orbit.multipliers"));
  o.start_distance = sc.real("orbit.start_distance");
  o.frames = static_cast<int>(sc.integer("orbit.frames"));
  o.theta = c.theta;
  o.state_scale = c.state_scale;
  o.step = c.step.initial;
  o.min_step = c.step.min;
  o.max_step = c.step.max;
  o.lambda_min = c.stop.lower;
  o.lambda_max = c.stop.upper;
  o.max_points = c.stop.max_steps;
  o.stops = c.events.stops;
  o.locate_tolerance = 1e-8;
  return o;
}

}  // namespace keller
