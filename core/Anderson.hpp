#pragma once

#include <deque>

#include "core/Types.hpp"

namespace keller {

// Anderson acceleration (type II, Walker & Ni 2011) of a fixed-point iteration x <- x + f(x), here
// the chord iteration with f = -M^{-1} F(x) for a fixed (old) factorisation M. From the last
// `depth` differences of iterates and of updates it takes the combination of past updates with
// the least norm and steps from there:
//   gamma = argmin |f_k - dF gamma|_2,   x_{k+1} = x_k + f_k - (dX + dF) gamma.
// On a linear problem it is GMRES on the preconditioned system in exact arithmetic (depth at
// least the iteration count), at the price of one residual and one solve per iteration, like the
// chord it accelerates; on a nonlinear one it cancels the few slowly contracting or oscillating
// modes that an old matrix leaves. The history must be reset when M changes.
class AndersonMixer {
 public:
  explicit AndersonMixer(int depth) : depth_(depth) {}
  int depth() const { return depth_; }
  void reset();
  // x: the current iterate, f: the chord update at it. Returns the increment to add to x (f itself
  // on the first call after a reset, or where the history is too ill-conditioned to use).
  Vector increment(const Vector& x, const Vector& f);
  // The same for an iterate (u, l) with its update (du, dl) (an unknown vector and a scalar, as
  // in a bordered system): (du, dl) becomes the increment.
  void mix(const Vector& u, double l, Vector& du, double& dl);
  int history() const { return static_cast<int>(dF_.size()); }

 private:
  int depth_;
  std::deque<Vector> dX_, dF_;
  Vector x_prev_, f_prev_;
  Vector x_, f_;  // (u, l) and (du, dl) stacked, for mix
};

}  // namespace keller
