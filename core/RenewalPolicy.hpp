// When a chord iteration (solves with the factorisation of an earlier Jacobian) should get a new
// Jacobian instead: one policy for core's Newton solver and the continuation's corrector, a pure
// function of the chord's history and goal (tested on synthetic residual sequences).
#pragma once

namespace keller {

// A chord that may go on slowly must reach its goal this many iterations before the limit (a
// margin for rates that worsen as the chord goes on).
inline constexpr int kChordSpareIterations = 2;

struct RenewalPolicy {
  // Keep the factorisation while |F| falls by at least this factor per iteration (0: never keep).
  double chord_rate = 0.25;
  // > 0: a chord slower than chord_rate goes on where, at its observed rate, it needs at most
  // this many more iterations (what a new Jacobian and its factorisation cost, counted in chord
  // iterations) and reaches its goal before the limit.
  double renewal_cost = 0.0;
  // Instead of the rate: keep while the chord, at its observed rate, reaches its goal before the
  // limit (a point located between two converged ones, where a few more solves are cheaper than a
  // factorisation).
  bool reach_goal = false;
  int max_iterations = 10;  // the solve's iteration limit
  // Below this residual a slower fall is rounding, not an old matrix: no renewal (0: none). Only
  // for rules that do not let the chord go on slowly (the convergence test then stops it).
  double floor_level = 0.0;

  struct History {
    int iteration = 1;             // iterations made so far in this solve (>= 1)
    int on_this_matrix = 1;        // of them with the present factorisation (>= 1)
    double residual = 0.0;         // |F|_inf now
    double previous = 0.0;         // one iteration ago
    double before_previous = 0.0;  // two ago (used where on_this_matrix >= 2)
    double goal = 0.0;             // the residual the solve aims at
    bool full_step = true;         // the last update was taken in full (not damped by a line search)
  };

  // The iterations the chord still needs to reach the goal at its observed rate (the mean rate of
  // its last two iterations on this matrix, which wander; the last one alone before that);
  // infinite when it does not contract.
  static double iterations_to_goal(const History& h);
  // Whether the next iteration should assemble and factorise a new Jacobian.
  bool renew(const History& h) const;
};

}  // namespace keller
