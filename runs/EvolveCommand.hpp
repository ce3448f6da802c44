// `keller evolve SCENE.toml -o RUN.h5 [--restart BRANCH.h5:ROW]`: integrates B du/dt = -F(u) in time
// (continuation/time/TimeIntegrator: adaptive BDF2) from the scene's steady state or from a point stored
// in a branch file, optionally perturbed along an eigenvector (computed at the start, or the one
// stored with the branch point), and writes the observables against time step by step to
// RUN.h5.part (readable at every moment, whatever ends the run), which takes the name RUN.h5 once
// the run has reached t_end, with the fields of the stored states and an XDMF file beside it. A run
// that was interrupted or killed leaves RUN.h5.part, and the same command continues it.
#pragma once

#include <string>
#include <vector>

#include "runs/RunSummary.hpp"

namespace keller {

struct EvolveArguments {
  std::string scene;
  std::string output;                  // empty: <scene stem>.h5 here
  std::string restart;                 // "FILE.h5:ROW" of a branch file (ROW a number or 'last'), or empty
  bool force = false;                  // start from a stored point that fails the compatibility checks
  bool fresh = false;                  // discard an unfinished RUN.h5.part instead of continuing it
  std::vector<std::string> overrides;  // "section.key=value"
};

// Exit codes of runs/ExitCode.hpp: 0 the run reached t_end or max_steps; 1 the first steady state
// failed (nothing written) or the step fell below min_step (RUN.h5.part holds every step before);
// 2 bad input (nothing written); 130 interrupted (RUN.h5.part holds every completed step).
int run_evolve(const EvolveArguments& args, RunSummary* summary = nullptr);

class SceneSchema;
// The keys `keller evolve` reads beyond the problem's: [evolve].
void declare_evolve_keys(SceneSchema& schema);

}  // namespace keller
