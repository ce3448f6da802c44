// When an iteration for F(u) = 0 has converged: at its residual goal, or at the rounding floor of
// the problem where the tolerance asks for less than floating point can give. One policy for
// core's Newton solver and the continuation's corrector (a pure function of the iterate's
// history, tested on synthetic sequences).
#pragma once

#include <limits>

#include "core/Types.hpp"

namespace keller {

// A residual that stops falling within this factor of the tolerance is taken for the rounding
// floor (large coupled systems sit at 1e-13 where a relative tolerance of 1e-10 asks 5e-15).
inline constexpr double kRoundingFloorBand = 1e3;
// An iteration whose residual falls by less than this factor has stopped falling.
inline constexpr double kStallRatio = 0.5;
// An iteration allowed to fall slowly (a chord kept past its rate) has stopped only when, in
// addition, two iterations together cut the residual by less than 10%.
inline constexpr double kSlowStallRatio = 0.9;
// Rounding at the floor wanders within a few times the smallest residual the iteration reached; a
// residual this many times that one is growing (an iteration on a matrix that is nearly singular
// along a direction the residual has a part in: next to a branch point), not at the floor.
inline constexpr double kFloorWander = 10.0;

// The rounding floor of F near u: the rounding error of evaluating its rows, estimated from the
// Jacobian as machine epsilon times max_i sum_j |J_ij| |u_j| (the size of the terms a row sums).
// A residual that stalls below it cannot be reduced by any iteration.
double rounding_floor(const SparseMatrix& J, const Vector& u);

struct ConvergenceTest {
  double tolerance = 0.0;         // |F|_inf aimed at (absolute)
  double goal = 0.0;              // a raised goal, >= tolerance where set (0: the tolerance)
  double update_tolerance = 0.0;  // relative: a full update below it (times max(|u|_inf, 1)) is rounding
  double problem_floor = 0.0;     // rounding_floor() of the problem near the iterate (0: unknown)
  // The iteration may fall slowly but steadily (a chord on a factorisation kept past its rate):
  // a stall must then hold over two iterations.
  bool slow = false;

  struct Iterate {
    double residual = 0.0;                                             // |F|_inf at this iterate
    double previous = std::numeric_limits<double>::infinity();         // at the iterate before
    double before_previous = std::numeric_limits<double>::infinity();  // two before
    double best = std::numeric_limits<double>::infinity();             // the smallest so far, the start's included
    // |du|_inf of the full update that led here, unaccelerated and undamped (infinite: none, or damped)
    double update = std::numeric_limits<double>::infinity();
    // the iteration's contraction per step (0: Newton on its own Jacobian); the steps still to
    // come then add up to about update * contraction / (1 - contraction)
    double contraction = 0.0;
    double scale = 1.0;  // max(|u|_inf, 1)
  };
  enum class Verdict { Continue, Converged, RoundingFloor };

  // The residual below which a stall, or an update at rounding level, is the rounding floor:
  // kRoundingFloorBand times the tolerance, or the problem's own floor where that is higher.
  double floor_level() const;
  double aim() const { return goal > tolerance ? goal : tolerance; }
  // Sets the goal of an iteration allowed to stop at rounding (a chord on a kept factorisation) to
  // the floor its neighbours reached (0: none known), never below the problem's own floor (where
  // the neighbours happened to land on an exact zero) and never above the floor level.
  void aim_at_floor(double neighbours_floor);
  Verdict judge(const Iterate& it) const;
};

}  // namespace keller
