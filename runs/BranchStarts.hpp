// The start modes of `keller trace` for a branch of the scene's own problem (runs/TraceStart): a
// fresh branch, an unfinished one continued, a restart or branch switch at a stored point, and a
// branch in another parameter from a stored state. Each returns what the run needs and says on
// the terminal where the branch starts.
#pragma once

#include "runs/TraceStart.hpp"

namespace keller {

// A fresh branch from the first steady state at the scene's parameter values (StartSolver: Newton
// from the problem's guess, then a path from an easier state where the scene allows one), its last
// factorisation handed to the run. Throws CommandFailure (exit 1, nothing written) where it fails.
TraceStart start_fresh(Problem& problem, const TraceSettings& settings);

// The unfinished branch of this command in `unfinished.file`, continued from its last stored row
// (with its tangent and the scales it was traced with).
TraceStart continue_unfinished(Problem& problem, const TraceSettings& settings, const Unfinished& unfinished);

// --restart or --switch: from the stored point of a branch in the run's parameter, with that
// branch's scales; a switch starts the branch through the stored branch point on the side
// `direction` (+1 or -1) of the old one.
TraceStart start_at_point(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                          const StoredPoint& stored, int direction);

// --restart from a branch traced in another parameter: a new branch from the stored state, at the
// point's values of every parameter (the run's own included, which a note compares with the
// scene's); its tangent and scales are its own. The point must record the run's parameter
// (read_trace_source checks it).
TraceStart start_in_other_parameter(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                                    const StoredPoint& stored, const Scene& scene);

}  // namespace keller
