// Branch points along a branch whose J is not factorised at every point (a kept factorisation).
// det of the bordered Jacobian [J F_p; c^T d], c along the tangent, keeps its sign through folds
// (det J and the tangent's parameter part change sign together there) and changes it at a simple
// branch point. Its sign is known wherever J is factorised: at every factorisation the corrector
// makes (at an iterate of a step), where a tangent falls back to a factorisation, and at probes
// this monitor asks for at accepted points where no factorisation came for kBranchPointProbeRows
// rows, and at the branch's last point. Where two successive signs differ, the branch point lies
// between the points that bracket them; bisection over the accepted points in between, probing
// each (a factorisation at the point), narrows that to one step, on which it is located as
// before. Without a kept factorisation every step has its sign, and the bracket is the step.
#pragma once

#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"

namespace keller {

// Accepted rows without a determinant sign of their own after which one is probed: bounds the
// bisection to log2 of it and the stretch of the branch checked late.
inline constexpr int kBranchPointProbeRows = 10;

class BranchPointMonitor {
 public:
  // The branch starts at start with the sign start.bordered_det_sign (exact: J factorised there).
  void restart(const BranchPoint& start);
  // Whether nxt (no sign of its own) should be probed: after kBranchPointProbeRows rows without
  // a sign, or where the branch ends at it (last).
  bool needs_probe(const BranchPoint& nxt, bool last) const;
  // nxt accepted after the last point with its sign (nxt.bordered_det_sign, 0: none; exact: J
  // factorised at nxt itself, else at an iterate of its step). Where the sign changed since the
  // last known one, the two neighbouring points that bracket the change, found by bisection with
  // probe(point) (a factorisation at it, returning its sign; 0 where that failed). Nothing where
  // there is no change (or a probe failed). nxt is then remembered.
  std::optional<std::pair<BranchPoint, BranchPoint>> accepted(const BranchPoint& nxt, bool exact,
                                                              const std::function<int(BranchPoint&)>& probe);
  // The last accepted point was reported under this row index.
  void reported(const BranchPoint& p);

 private:
  // the points since (and including) the one before the last signed point, in order, with
  // whether the last sign was exact at its point
  std::vector<BranchPoint> history_;
  size_t signed_ = 0;  // index in history_ of the last point with a sign
  bool exact_ = true;
  int sign_ = 0;
};

}  // namespace keller
