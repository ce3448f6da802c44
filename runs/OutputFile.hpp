// Writing a run's HDF5 file so that a failure never leaves a partial file under the final name:
// everything goes to OUT.h5.part, renamed to OUT.h5 when complete.
#pragma once

#include <string>
#include <vector>

#include "core/H5File.hpp"
#include "core/Problem.hpp"
#include "core/Scene.hpp"

namespace keller {

// Checks that the output can be written (directory exists and is writable; not a directory
// itself); throws SceneError-like std::runtime_error with a clear message otherwise.
void check_output_path(const std::string& path);

// The XDMF path beside an HDF5 path: OUT.h5 -> OUT.xdmf.
std::string xdmf_path_for(const std::string& h5_path);

// Writes /scene, /problem (name, summary, unknowns) and /parameters attributes.
void write_run_header(H5File& file, const Scene& scene, const Problem& problem);

// Writes a solution's fields, parameter values and observables under `group`.
void write_solution(H5File& file, const std::string& group, Problem& problem, const Vector& u);

}  // namespace keller
