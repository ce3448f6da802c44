// Options of the continuation engine: which named parameter, how to step, where to stop, what
// to locate. Plain struct with defaults; declare() lists the scene keys of [continuation].
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/Scene.hpp"

namespace keller {

struct ContinuationOptions {
  enum class Method { Arclength, Natural };
  enum class Predictor { Tangent, Secant };

  std::string parameter;                 // named parameter of the problem
  Method method = Method::Arclength;     // Keller's pseudo-arclength, or natural (parameter) steps
  Predictor predictor = Predictor::Tangent;
  int direction = +1;                    // initial sign of the parameter change
  double lower = -std::numeric_limits<double>::infinity();  // the branch ends where the parameter
  double upper = std::numeric_limits<double>::infinity();   // reaches a bound (located exactly)
  std::vector<double> stops;             // parameter values where solutions are wanted
  // Pseudo-arclength: a step whose predictor would cross a stop or a bound is shortened to land
  // on it and corrected at that parameter value (one correction instead of a step past it and a
  // located correction; never a step beyond a bound). Off: such points are located on the step
  // that crosses them.
  bool land_on_values = true;

  // Step sizes: arclength in the weighted norm below (natural method: parameter units).
  double initial_step = 0.05;
  double min_step = 1e-8;
  double max_step = 1.0;
  int max_steps = 1000;
  // Corrector: Newton (one factorisation of the bordered matrix per iteration) or chord (the
  // factorisation of the first iteration reused while the residual falls by at least
  // chord_rate per iteration; refactorised when it does not).
  enum class Corrector { Newton, Chord };
  // Bordered solves: factorise the whole extended matrix, or eliminate on J's factorisation
  // (falls back to the whole matrix where J is singular); see BorderedSystem.
  bool block_elimination = false;
  Corrector corrector = Corrector::Newton;
  double chord_rate = 0.25;
  // Chord corrector with block elimination: keep J's factorisation across steps too (a new one
  // when the chord rate fails in a step, and at a located point only when the chord at its
  // observed rate would need more than max_iterations), tangents by iterating with the kept factorisation on the
  // exact tangent system of the new point (a factorisation there only if that iteration does
  // not converge). With detect_branch_points the determinant must be exact: every accepted
  // point then gets its own factorisation.
  bool reuse_factorisation = false;
  // With reuse_factorisation: a step's chord slower than chord_rate goes on without a new
  // factorisation where, at its observed rate, it needs at most this many more solves (what a
  // factorisation costs in solves, counting the iterations after it). 0: the rate rule alone.
  double renewal_cost = 0.0;
  // Chord corrector: Anderson acceleration of the iterations on one factorisation, over this many
  // past updates (0: plain chord). Its combination of past updates cancels the slow or
  // oscillating modes that an old matrix leaves, at no extra solve.
  int anderson_depth = 0;
  int target_iterations = 4;   // grow the step when the corrector needs fewer, shrink when more
  int max_iterations = 10;     // corrector iterations before a step counts as failed
  double growth = 1.5;
  double shrink = 0.5;         // factor on failure or on too many iterations
  double max_angle_degrees = 20.0;  // between successive unit tangents

  // Arclength norm |(du, dp)|^2 = theta |du|^2 / (n s^2) + (1 - theta) dp^2, s the state scale
  // (root mean square of the starting solution, or 1 if that is zero) so that states of any
  // magnitude weigh alike.
  double theta = 0.5;
  double state_scale = 0.0;    // 0: automatic

  double event_tolerance = 1e-8;    // absolute, in the parameter
  int max_location_iterations = 60;
  bool detect_folds = true;
  bool detect_branch_points = true;
  int save_every = 10;              // full solutions of every N-th point (and of every located point)

  std::string stop_observable;      // stop where this observable crosses stop_above / stop_below
  double stop_above = std::numeric_limits<double>::infinity();
  double stop_below = -std::numeric_limits<double>::infinity();

  static void declare(SceneSchema& schema);
  static ContinuationOptions from_scene(const Scene& scene);
  // Throws std::invalid_argument with a message naming the option.
  void validate() const;
};

}  // namespace keller
