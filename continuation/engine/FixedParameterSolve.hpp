// Newton's method on F(u) = 0 at fixed parameters through the continuation's bordered solves:
// the corrector (Corrector) under the row "parameter = its value", with block elimination on J's
// factorisation, which for a problem with a border of its own (an augmented problem) is its inner
// matrix. The first point of a curve costs factorisations of the inner problem's J, not of the
// whole augmented matrix; given a factorisation made nearby (another run's), the chord on it.
#pragma once

#include <string>

#include "continuation/engine/KeptFactorisation.hpp"
#include "core/Newton.hpp"
#include "core/Problem.hpp"
#include "core/SparseLU.hpp"

namespace keller {

struct FixedParameterResult {
  Status status;  // ok: converged
  int iterations = 0;
  long factorisations = 0;
  double seconds = 0.0;
  StartFactorisation factorisation;  // the one in use at the end (for a run from the solution)
};

// Solves F(u) = 0 from u (in place) with every parameter at its present value; parameter: any of
// the problem's parameters (the bordered system's extra column is its dF/dp). Newton's tolerances
// and iteration limit from newton; no line search (the start is a located point, close to the
// solution). With `near` (J's or the inner matrix's factorisation made at a nearby state): the
// chord on it, renewed where the renewal policy asks; else Newton.
FixedParameterResult solve_at_fixed_parameter(Problem& problem, const std::string& parameter, Vector& u,
                                              const NewtonOptions& newton, const SparseLUOptions& lu,
                                              const StartFactorisation& near = {});

}  // namespace keller
