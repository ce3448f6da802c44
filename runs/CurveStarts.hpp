// The start modes of `keller trace --from FILE.h5:ROW --curve fold|hopf|event --free P2`
// (runs/TraceStart): the curve of the located point stored at ROW, continued in the second
// parameter P2 (the run's), the parameter of its branch an unknown of the curve. The curve starts
// at the stored point, corrected onto the curve at the point's parameter values; an unfinished
// curve of this command (`unfinished`, or null) continues from its last stored row. Each throws
// CommandFailure: bad input where the stored point cannot start the curve, a numerical failure
// (exit 1, nothing written) where the curve's first point fails.
#pragma once

#include "runs/TraceStart.hpp"

namespace keller {

// The fold curve (FoldCurveProblem) from a located fold, its null vector guessed by the stored tangent.
TraceStart start_fold_curve(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                            const StoredPoint& stored, const Unfinished* unfinished);

// The Hopf curve (HopfCurveProblem) from a located Hopf point of a branch traced with its stability,
// from the critical eigenvector stored with it.
TraceStart start_hopf_curve(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                            const StoredPoint& stored, const Unfinished* unfinished);

// The event curve (EventCurveProblem) from a located zero of a monitor that is a minimum over
// places (an event, or the end at the stop observable's threshold), following the minimum's place:
// each piece of the curve ends where the place moves (its switch margin is the stop observable, the
// scene's is left aside, saying so).
TraceStart start_event_curve(Problem& problem, const TraceSettings& settings, const StoredStart& from,
                             const StoredPoint& stored, const Unfinished* unfinished);

}  // namespace keller
