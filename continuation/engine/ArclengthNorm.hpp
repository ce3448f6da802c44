// The weighted inner product of pseudo-arclength continuation and the linear constraints that close
// the bordered system, in one place:
//   <(u1, l1), (u2, l2)> = wu u1.u2 + wl l1 l2,  wu = theta / (n s^2),  wl = 1 - theta,
// s the state scale (so that states of any magnitude weigh alike); a constraint is a row
//   cu . (u - u0) + cl (lambda - l0) = target.
#pragma once

#include "continuation/engine/BranchPoint.hpp"
#include "core/Types.hpp"

namespace keller {

// A linear constraint closing the extended system [F; N] = 0 (its row is the border row).
struct Constraint {
  Vector cu;  // empty: zero
  double cl = 0.0;
  const Vector* u0 = nullptr;  // the point the row is measured from (with cu; null: the origin)
  double l0 = 0.0;
  double target = 0.0;
  // N(u, lambda) = cu . (u - u0) + cl (lambda - l0) - target
  double value(const Vector& u, double lambda) const;
  // lambda = value: the natural-parameter row
  static Constraint parameter(double value);
};

class ArclengthNorm {
 public:
  ArclengthNorm() = default;
  // n unknowns, state scale s > 0, theta in (0, 1)
  ArclengthNorm(int n, double state_scale, double theta);
  double state_scale() const { return scale_; }
  double wu() const { return wu_; }
  double wl() const { return wl_; }
  double dot(const Vector& u1, double l1, const Vector& u2, double l2) const {
    return wu_ * u1.dot(u2) + wl_ * l1 * l2;
  }
  double norm(const Vector& u, double l) const;
  // The distance between two points of a branch.
  double distance(const BranchPoint& a, const BranchPoint& b) const;
  // The pseudo-arclength row: <(u - from.u, lambda - from.lambda), (tu, tl)> = sigma.
  Constraint arclength(const BranchPoint& from, const Vector& tu, double tl, double sigma) const;
  // The row <(u, l), (tu, tl)> through the tangent alone (border row of a tangent system).
  Constraint tangent_row(const Vector& tu, double tl) const;

 private:
  double scale_ = 1.0, wu_ = 0.0, wl_ = 1.0;
};

}  // namespace keller
