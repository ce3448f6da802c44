// The start of an orbit branch from a `keller evolve` run that reached a limit cycle
// (`keller trace --orbit --from RUN.h5`): its last state, and a period estimated from its time
// table, both checked against the scene.
#pragma once

#include <string>
#include <vector>

#include "core/Problem.hpp"
#include "core/Types.hpp"

namespace keller {

struct LoadedScene;

// Whether `path` names an existing HDF5 file written by keller evolve (it has /evolve).
bool is_time_series(const std::string& path);

struct EvolveStart {
  Vector u;                // the run's last state
  double t = 0.0;          // its time
  double period = 0.0;     // estimated from `observable` over the second half of the run
  std::string observable;  // the one with the largest swing there, relative to its size
  double parameter = 0.0;  // the value of the branch's parameter in the run
};

// Reads the last state of the time series at `path` and estimates its period
// (oscillation_period, continuation/orbits/OrbitMeasures) from the observable that swings most,
// relative to its magnitude, over the run's second half. The run must have been made by this
// scene's problem and physics, at its parameter values except `parameter` (whose value is then the
// run's); with `force` a difference is a warning. Throws std::invalid_argument naming the file and
// what is wrong (another problem, too few periods integrated, no oscillation).
EvolveStart read_evolve_start(const std::string& path, const LoadedScene& scene, Problem& problem,
                              const std::string& parameter, bool force, std::vector<std::string>& warnings);

}  // namespace keller
