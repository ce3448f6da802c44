// `keller solve SCENE.toml -o OUT.h5`: one steady state by Newton's method, written as HDF5
// (resolved scene, mesh, fields, parameters, observables, Newton history) plus XDMF.
#pragma once

#include <string>
#include <vector>

#include "runs/RunSummary.hpp"

namespace keller {

struct SolveArguments {
  std::string scene;
  std::string output;                  // empty: <scene stem>.h5 in the current directory
  std::vector<std::string> overrides;  // "section.key=value"
  bool output_locked = false;          // the caller holds OUT.h5.lock (a study's task): not taken again
  // J and dF/dp against central differences at the initial guess and near it (core/JacobianCheck)
  // before Newton: a failed check exits 1 with nothing written
  bool check_jacobian = false;
};

// Returns the process exit code: 0 converged, 1 Newton (or the Jacobian check) failed (no output written),
// 2 bad input (no output written).
int run_solve(const SolveArguments& args, RunSummary* summary = nullptr);

struct LoadedScene;
// What defines a solve (its resolved scene's values), as stored in its file (/problem/run).
std::string solve_run_record(const LoadedScene& loaded);

}  // namespace keller
