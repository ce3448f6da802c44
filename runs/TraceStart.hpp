// How `keller trace` begins. What the run starts from is read first (read_trace_source: the
// unfinished run of this command, the stored point of --restart, --switch or --from); then one
// start mode turns it into a TraceStart, what the run needs: the problem the stepper continues
// (the scene's, or a curve's augmented problem), where and how it begins, and the options it runs
// with. The modes are functions of their own (runs/BranchStarts: a fresh branch, an unfinished one
// continued, a restart or switch, a branch in another parameter; runs/CurveStarts: fold, Hopf and
// event curves); trace_start picks the one the command line asks for.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "continuation/curves/CurveProblem.hpp"
#include "continuation/curves/EventCurveProblem.hpp"
#include "continuation/curves/EventCurveTracer.hpp"
#include "continuation/output/BranchFile.hpp"
#include "continuation/start/StartSolver.hpp"
#include "core/Newton.hpp"
#include "core/SparseLU.hpp"
#include "runs/StoredStart.hpp"
#include "stability/StabilityAnalysis.hpp"

namespace keller {

class CommandRun;

// The options of a trace, as its scene sets them ([continuation], [stability], [newton],
// [linear_solver], [start]); the continuation's parameter is --free's for a curve.
struct TraceSettings {
  ContinuationOptions continuation;
  StabilityOptions stability;
  NewtonOptions newton;
  SparseLUOptions lu;
  StartOptions start;
  // Throws SceneError naming the key of a value it refuses.
  static TraceSettings from_scene(const Scene& scene, const std::string& free = "");
};

// The unfinished run of this very command, continued from its last stored row.
struct Unfinished {
  std::string file;                   // OUT.h5.part
  BranchSeed seed;                    // its rows up to the last one with a stored solution (seed.row)
  BranchPoint point;                  // that row's point
  double state_scale = 0, theta = 0;  // the scales its branch was traced with
};

// What a trace starts from, read before anything is computed.
struct TraceSource {
  LeftRun left;                          // what an earlier run of this command left in OUT.h5.part
  std::optional<Unfinished> unfinished;  // its unfinished run, to be continued
  std::optional<StoredPoint> stored;     // the point of --restart, --switch or --from
  std::vector<std::string> warnings;     // the refusals --force let through
};

// Reads what the run in `run` (its record `record`, trace_run_record) starts from: what an earlier
// run left (`fresh` discards it), and the stored point `from` names (checked against the scene and
// `problem` for a run in `parameter`; not read where an unfinished branch is continued, whose
// start it was). Nothing more is read where the earlier run ended and waits to be published.
// Throws std::invalid_argument naming the file, the row and what is wrong.
TraceSource read_trace_source(const CommandRun& run, const std::string& record, bool fresh,
                              const std::optional<StoredStart>& from, const Problem& problem,
                              const std::string& parameter);

struct TraceStart {
  // How the stepper begins: from a state (its first tangent its own), from a stored point (with
  // the tangent stored with it), by switching branches at a stored branch point, or along the
  // pieces of an event curve from its first state.
  enum class Begin { State, Point, Switch, EventCurve };
  Begin begin = Begin::State;
  Vector state;                              // State, EventCurve: the first state
  StartFactorisation factorisation;          // State after a solve: its last factorisation of J
  std::optional<BranchPoint> point;          // Point, Switch: the stored point
  int direction = +1;                        // Switch: the side of the old branch
  ContinuationOptions options;               // the run's: the scene's, a continued branch's scales, a curve's stops
  std::unique_ptr<CurveProblem> curve;       // a curve's augmented problem, traced instead of the scene's
  EventCurveProblem* event_curve = nullptr;  // EventCurve: `curve`, whose pieces it traces
  std::unique_ptr<EventCurveTracer> event_tracer;  // EventCurve: runs the pieces of `event_curve`
  // A fold or Hopf curve: the observer that moves the curve's borders to each point before `next`
  // sees it (CurveBorderUpdate).
  std::function<std::unique_ptr<BranchObserver>(BranchObserver& next)> borders;
  std::optional<BranchSeed> seed;  // an unfinished run continued: the rows its file takes over

  // The problem the stepper continues: the curve's, else the scene's `problem`.
  Problem& traced(Problem& problem) const { return curve ? *curve : problem; }
  // The state the branch begins at.
  const Vector& first_state() const { return point ? point->u : state; }
};

// The start mode the command line asks for (`from`: --restart, --switch or --from; `direction`:
// --switch-direction), from what `source` holds, for the scene `scene` and its `problem`. A run
// without a state scale of its own takes the RMS of its first state (1 where that is 0). Throws
// CommandFailure: bad input, or a numerical failure of the first state (nothing written).
TraceStart trace_start(Problem& problem, const TraceSettings& settings, const std::optional<StoredStart>& from,
                       const TraceSource& source, const Scene& scene, int direction);

// What the start modes share: the parameter values of the stored point (the values of its branch
// and the point's own) set in `problem`; the line that says a run continues `unfinished` ("branch",
// "curve": `what`) in `parameter`.
void use_stored_parameters(Problem& problem, const StoredPoint& stored);
void say_continuing(const std::string& what, const Unfinished& unfinished, const std::string& parameter);

}  // namespace keller
