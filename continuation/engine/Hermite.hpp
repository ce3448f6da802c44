// The cubic Hermite interpolant of two points of a branch and their tangents: the predictor for
// points located between them (error O(h^4) against O(h^2) for the straight chord).
#pragma once

#include <functional>
#include <optional>

#include "continuation/engine/BranchPoint.hpp"

namespace keller {

// A linear functional of (u, lambda): g(u, lambda, true) at a point, g(tu, tlambda, false) its
// linear part along a tangent (for a functional with no offset the two are the same).
using BranchFunctional = std::function<double(const Vector&, double, bool)>;

// The point (u, lambda) on the cubic through a and b with derivatives a.t and b.t with respect to
// s (a.s < b.s) where g equals target; x in [0, 1] is where along the segment. False, with u and
// lambda untouched, where the cubic does not take the value on the segment (a fold inside it) or
// a point lacks its tangent.
bool hermite_point(const BranchPoint& a, const BranchPoint& b, const BranchFunctional& g, double target, Vector& u,
                   double& lambda, double& x);

// The cubic through a and b (a.s < b.s) continued beyond b by sigma of arclength: (u, lambda) at
// s = b.s + sigma. False, with u and lambda untouched, where a point lacks its tangent.
bool hermite_extrapolate(const BranchPoint& a, const BranchPoint& b, double sigma, Vector& u, double& lambda);
// The sigma beyond b where g along the continued cubic equals target, by Newton from sigma0 (the
// cubic then takes it to 1e-12 of the values' scale); nullopt where Newton does not get there.
std::optional<double> hermite_extrapolate_to(const BranchPoint& a, const BranchPoint& b, const BranchFunctional& g,
                                             double target, double sigma0);

}  // namespace keller
