// The direction of a new branch at a branch point: the null vector phi of J there (inverse
// iteration on J's factorisation: J is nearly singular, so each solve multiplies its share by the
// inverse of the smallest singular value), made orthogonal to the old tangent in the arclength
// norm; (phi, 0) lies in the null space of [J F_p] there, as the old tangent does. The old tangent
// is the located point's, which the locator takes from the regular points that bracket it (the
// tangent system is singular at the branch point itself and would return phi).
#pragma once

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/BranchPoint.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "core/SparseLU.hpp"

namespace keller {

// Inverse iteration for the null vector: from a generic start, the share of the null vector grows
// by (the next smallest eigenvalue of J over the smallest) per step, large where the branch point
// is located much closer than the spectrum's spacing near zero, but not necessarily (a problem with many
// small eigenvalues, such as slow diffusive modes, separates them slowly). So it iterates until the
// direction changes by less than kNullVectorTolerance, at most kNullVectorMaxIterations solves on
// the one factorisation, instead of a fixed three.
inline constexpr int kNullVectorMaxIterations = 100;
inline constexpr double kNullVectorTolerance = 1e-10;

// The unit direction (tu, tl) of the branch that crosses the old one at bp; direction +1 or -1
// picks the side (+1: the largest entry of the null vector grows). A status where J cannot be
// factorised or the null vector is the old tangent.
Status branch_direction(Evaluator& ev, const SparseLUOptions& lu_options, const ArclengthNorm& norm,
                        const BranchPoint& bp, int direction, Vector& tu, double& tl);

}  // namespace keller
