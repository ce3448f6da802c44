// The direction of a new branch at a branch point: the null vector phi of J there (inverse
// iteration on J's factorisation: J is nearly singular, so each solve multiplies its share by the
// inverse of the smallest singular value), made orthogonal to the old tangent in the arclength
// norm; (phi, 0) lies in the null space of [J F_p] there, as the old tangent does.
#pragma once

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/BranchPoint.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "core/SparseLU.hpp"

namespace keller {

// Inverse-iteration steps for the null vector: from a generic start, the share of the null
// vector grows by 1 / (the smallest singular value over the next) per step.
inline constexpr int kNullVectorIterations = 3;

// The unit direction (tu, tl) of the branch that crosses the old one at bp; direction +1 or -1
// picks the side (+1: the largest entry of the null vector grows). A status where J cannot be
// factorised or the null vector is the old tangent.
Status branch_direction(Evaluator& ev, const SparseLUOptions& lu_options, const ArclengthNorm& norm,
                        const BranchPoint& bp, int direction, Vector& tu, double& tl);

}  // namespace keller
