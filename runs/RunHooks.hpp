// What a program that runs keller's commands in its own process (the Python package, python/)
// sees of a run as it goes: each point of a branch (`trace`) and each accepted step of a time
// integration (`evolve`), after it is written to the run's file. A hook that returns false stops
// the run as Ctrl-C does (InterruptGuard::request): the run keeps what it completed in OUT.h5.part,
// exits 130, and the same command continues it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "continuation/time/TimeIntegrator.hpp"
#include "core/Types.hpp"

namespace keller {

struct RunPoint {
  std::string command;             // "trace" or "evolve"
  int row = 0;                     // the branch row, or the step (0: the start)
  std::string kind;                // a branch point's kind as the CSV names it ("point", "fold", ...); "step"
  std::string label;               // a located point's monitor or bound ("max" / "min" at a fold); empty
  std::vector<std::string> names;  // the parameter (evolve: "t"), the observables, then the monitors
  std::vector<double> values;      // their values at the point
  const Vector* u = nullptr;       // the state, valid during the call
};

using RunHook = std::function<bool(const RunPoint&)>;

// Sets the hook of the commands that run while it lives (one command runs at a time in a process).
class RunHookScope {
 public:
  explicit RunHookScope(RunHook hook);
  ~RunHookScope();
  RunHookScope(const RunHookScope&) = delete;
  RunHookScope& operator=(const RunHookScope&) = delete;
};

// An observer that calls the process's hook (null where none is set) for every point of a branch
// traced in `parameter`, or for every step of a time integration with the problem's observables
// `observables`.
std::unique_ptr<BranchObserver> branch_hook(const std::string& parameter);
std::unique_ptr<TimeObserver> time_hook(Problem& problem);

}  // namespace keller
