// The UMFPACK backend of core/SparseLU, and the translation of SparseLUOptions into UMFPACK's
// controls and of its status codes into a Status, shared with the complex LU of stability/.
#pragma once

#include <memory>
#include <string>

#include "core/LUBackend.hpp"

namespace keller {

inline constexpr int kUmfpackControlSize = 20;  // UMFPACK_CONTROL (checked in UmfpackLU.cpp)

// UMFPACK's defaults with the options' ordering, scaling, strategy, pivot tolerance and refinement
// steps; `control` holds kUmfpackControlSize entries.
void umfpack_control(const SparseLUOptions& options, double* control);
// Ok for UMFPACK_OK and the determinant's under/overflow warnings; SingularMatrix for a singular
// matrix; LinearSolverError otherwise. `what` names the step ("numeric factorisation").
Status umfpack_status(int status, const std::string& what);

std::unique_ptr<LUBackend> make_umfpack_lu(const SparseLUOptions& options);

}  // namespace keller
