// `keller trace SCENE.toml --from BRANCH.h5:ROW --orbit -o OUT.h5`: the branch of periodic orbits
// born at the located Hopf point stored in BRANCH.h5:ROW (continuation/orbits), in the scene's
// continuation parameter, with each orbit's period, amplitudes and Floquet multipliers and the
// located folds, period doublings and Neimark-Sacker points of orbits, written point by point to
// OUT.h5.part as a branch file (u0 as each row's solution) that takes the name OUT.h5 once the
// branch has ended. It starts from the normal form's orbit (amplitude from l1) on the side where
// the orbits exist; [orbit] sets its integrator, tolerances and multipliers (docs/periodic_orbits.md).
// A row that is not a located Hopf point, or a problem without a mass matrix, is refused before
// any work.
#pragma once

#include "runs/RunSummary.hpp"
#include "runs/TraceCommand.hpp"

namespace keller {

// Exit codes as run_trace's.
// Why an orbit branch refuses [stability] on (the orbit command, and a study of orbit branches).
extern const char* const kOrbitStabilityRefusal;
int run_orbit_trace(const TraceArguments& args, RunSummary* summary = nullptr);

}  // namespace keller
