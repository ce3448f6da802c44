// Synthetic points of a branch for the tests of the engine's parts on given inputs (the crossings
// of a segment, determinant signs, counts).
#pragma once

#include <utility>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"

namespace keller::test {

// A point at arclength s and parameter lambda, with the parameter part of its tangent and its
// monitors.
inline BranchPoint point(double s, double lambda, double tlambda, std::vector<double> monitors) {
  BranchPoint p;
  p.s = s;
  p.lambda = lambda;
  p.tlambda = tlambda;
  p.monitors = std::move(monitors);
  return p;
}

}  // namespace keller::test
