#include "runs/study/TaskScenes.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/orbits/OrbitContinuation.hpp"
#include "runs/OrbitCommand.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SolveCommand.hpp"
#include "runs/TraceCommand.hpp"
#include "stability/StabilityAnalysis.hpp"

namespace keller {

LoadedScene TaskScenes::load(const StudyTask& task) {
  auto it = texts_.find(task.scene);
  if (it == texts_.end()) {
    std::ifstream in(task.scene, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    // a file that cannot be read: load_scene says so as for any run
    if (!in) return load_scene(task.scene, declare_trace_keys, task.overrides);
    it = texts_.emplace(task.scene, text.str()).first;
  }
  LoadedScene loaded = load_scene_text(it->second, task.scene, declare_trace_keys, task.overrides);
  if (kind_ == "solve") return loaded;
  const ContinuationOptions continuation = ContinuationOptions::from_scene(loaded.scene);
  if (kind_ == "orbit") {
    OrbitContinuationOptions::from_scene(loaded.scene, continuation);
    if (StabilityOptions::from_scene(loaded.scene).enabled)
      throw SceneError(fmt::format("key 'stability.enabled': {}: set stability.enabled = false for an orbit study",
                                   kOrbitStabilityRefusal));
  }
  return loaded;
}

std::string TaskScenes::run_record(const StudyTask& task, const LoadedScene& loaded) const {
  if (kind_ == "solve") return solve_run_record(loaded);
  TraceArguments a;
  if (kind_ == "orbit") {
    a.from = task.start;
    a.orbit = true;
  } else {
    a.restart = task.start;
  }
  return trace_run_record(loaded, a);
}

std::string TaskScenes::shape(const LoadedScene& loaded) const {
  std::string key = loaded.scene.source() + "\n" + loaded.physics();
  if (kind_ == "orbit") {
    const ContinuationOptions o = ContinuationOptions::from_scene(loaded.scene);
    key +=
        fmt::format("\norbit\n{}\n{}", o.parameter, OrbitContinuationOptions::from_scene(loaded.scene, o).multipliers);
  } else if (kind_ == "trace") {
    const ContinuationOptions o = ContinuationOptions::from_scene(loaded.scene);
    const StabilityOptions stability = StabilityOptions::from_scene(loaded.scene);
    key += fmt::format("\n{}\n{}\n{}\n{}\n{}", o.parameter, o.stop.observable, std::isfinite(o.stop.above),
                       std::isfinite(o.stop.below), stability.enabled ? stability.count : -1);
  }
  return text_hash(key);
}

std::string TaskScenes::problem(const LoadedScene& loaded) {
  return text_hash(loaded.scene.source() + "\n" + loaded.physics());
}

}  // namespace keller
