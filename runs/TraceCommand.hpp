// `keller trace SCENE.toml -o OUT.h5 [--restart FILE.h5:ROW | --switch FILE.h5:ROW |
// --from FILE.h5:ROW --curve fold|hopf|event --free PARAMETER]`: traces a solution branch with the
// continuation engine, or the curve of the fold, Hopf point or event located at a stored row in a second
// parameter (continuation/curves/FoldCurveProblem, HopfCurveProblem, EventCurveProblem; [continuation] then sets the
// curve's range, stops and steps). The branch is written
// point by point to OUT.h5.part (readable at every moment, whatever ends the run) and takes the name OUT.h5 once the
// branch has ended, with the fields of its stored solutions and an XDMF file beside it. A run that was interrupted or
// killed leaves OUT.h5.part, and the same command continues it from its last stored solution; a branch that ended at
// the step-size floor (or could not start) does not replace an existing OUT.h5.
#pragma once

#include <string>
#include <vector>

#include "runs/RunSummary.hpp"

namespace keller {

struct TraceArguments {
  std::string scene;
  std::string output;                  // empty: <scene stem>.h5 here
  std::string restart;                 // "FILE.h5:ROW" (ROW may be "last"), or empty
  std::string switch_at;               // "FILE.h5:ROW": a new branch from the branch point stored there
  int switch_direction = +1;           // which side of the old branch (+1 or -1)
  std::string from;                    // "FILE.h5:ROW": a curve from the located point stored there
  std::string curve;                   // what --from continues: "fold", "hopf" or "event"
  std::string free;                    // the curve's second parameter (empty: continuation.parameter)
  bool orbit = false;                  // --orbit: the branch of periodic orbits from the Hopf point of --from
  bool force = false;                  // start from a stored point that fails the compatibility checks
  bool fresh = false;                  // discard an unfinished OUT.h5.part instead of continuing it
  bool output_locked = false;          // the caller holds OUT.h5.lock (a study's task): not taken again
  std::vector<std::string> overrides;  // "section.key=value"
};

// Exit codes of runs/ExitCode.hpp: 0 the branch ended at a bound, the stop observable or
// max_steps; 1 the first steady state failed (nothing written) or the branch ended at the step
// floor; 2 bad input (nothing written); 130 interrupted (OUT.h5.part holds every completed point).
// `summary`, when given, receives what a study collects about the run.
int run_trace(const TraceArguments& args, RunSummary* summary = nullptr);
class SceneSchema;
// The keys `keller trace` reads beyond the problem's: [continuation] and [stability].
void declare_trace_keys(SceneSchema& schema);

struct LoadedScene;
// What defines a run (its resolved scene's values and how it starts), as stored in its branch
// file (/problem/run): a rerun of the same command recognises its unfinished file by it, and a
// study its completed tasks.
std::string trace_run_record(const LoadedScene& loaded, const TraceArguments& args);

}  // namespace keller
