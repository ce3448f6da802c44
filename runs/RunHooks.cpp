#include "runs/RunHooks.hpp"

#include <algorithm>
#include <utility>

#include "runs/Interrupts.hpp"

namespace keller {

namespace {

RunHook g_hook;

// Calls the hook; false stops the run as a signal does.
void call_hook(const RunPoint& point) {
  if (g_hook && !g_hook(point)) InterruptGuard::request();
}

// Only values with a name: a value the observer was not told the name of (none in a run: the
// continuation names its monitors and stop thresholds at its start) is left out, never unnamed.
RunPoint& named(RunPoint& point) {
  const size_t n = std::min(point.names.size(), point.values.size());
  point.names.resize(n);
  point.values.resize(n);
  return point;
}

class BranchHook final : public BranchObserver {
 public:
  explicit BranchHook(std::string parameter) : parameter_(std::move(parameter)) {}
  void on_start(const std::vector<std::string>& observables, const std::vector<std::string>& monitors) override {
    names_ = {parameter_};
    names_.insert(names_.end(), observables.begin(), observables.end());
    names_.insert(names_.end(), monitors.begin(), monitors.end());
  }
  void on_point(const BranchPoint& p) override {
    RunPoint point{"trace", p.index, to_string(p.kind), p.label, names_, {p.lambda}, &p.u};
    point.values.insert(point.values.end(), p.observables.begin(), p.observables.end());
    point.values.insert(point.values.end(), p.monitors.begin(), p.monitors.end());
    call_hook(named(point));
  }

 private:
  std::string parameter_;
  std::vector<std::string> names_;
};

class TimeHook final : public TimeObserver {
 public:
  explicit TimeHook(Problem& problem) : problem_(problem), names_(problem.observable_names()) {
    names_.insert(names_.begin(), "t");
  }
  void on_step(const TimePoint& p) override {
    RunPoint point{"evolve", p.step, "step", "", names_, {p.t}, &p.u};
    std::vector<double> observables;
    if (names_.size() > 1 && problem_.observables(p.u, observables).is_ok())
      point.values.insert(point.values.end(), observables.begin(), observables.end());
    call_hook(named(point));
  }

 private:
  Problem& problem_;
  std::vector<std::string> names_;
};

}  // namespace

RunHookScope::RunHookScope(RunHook hook) { g_hook = std::move(hook); }
RunHookScope::~RunHookScope() { g_hook = nullptr; }

std::unique_ptr<BranchObserver> branch_hook(const std::string& parameter) {
  return g_hook ? std::make_unique<BranchHook>(parameter) : nullptr;
}

std::unique_ptr<TimeObserver> time_hook(Problem& problem) {
  return g_hook ? std::make_unique<TimeHook>(problem) : nullptr;
}

}  // namespace keller
