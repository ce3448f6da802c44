// The MUMPS backend of core/SparseLU (sequential MUMPS, Debian's libmumps-seq): the matrix is
// given to MUMPS as centralised triplets, analysed once per pattern (JOB = 1; the ordering `best`
// keeps the candidate with the fewest estimated flops), factorised per call (JOB = 2, with the
// determinant, ICNTL(33)) and solved with MUMPS's iterative refinement (JOB = 3). Built only where
// CMake found MUMPS (KELLER_MUMPS).
#pragma once

#include <memory>

#include "core/LUBackend.hpp"

namespace keller {

std::unique_ptr<LUBackend> make_mumps_lu(const SparseLUOptions& options);

}  // namespace keller
