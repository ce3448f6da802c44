// The scenes of a study's tasks: each base scene file read once, and each task's scene loaded
// from it with the task's overrides (as `--set` would), with what a study keeps of it: the
// record of the run it defines and the keys that shape its output.
#pragma once

#include <map>
#include <string>

#include "runs/SceneLoader.hpp"
#include "runs/study/Study.hpp"

namespace keller {

class TaskScenes {
 public:
  explicit TaskScenes(std::string kind) : kind_(std::move(kind)) {}  // "trace", "solve" or "orbit"

  // The task's scene, validated (for a trace, its [continuation] too). Throws SceneError as
  // load_scene does.
  LoadedScene load(const StudyTask& task);
  // What defines the task's run: the resolved scene and the start (trace_run_record,
  // solve_run_record).
  std::string run_record(const StudyTask& task, const LoadedScene& loaded) const;
  // A hash of what the names in the task's output depend on (the scene file, the physics, and for
  // a trace the parameter, the stop observable and its thresholds, the stability columns): tasks
  // of the same shape have the same columns, monitors and observables (Study::check_collect).
  std::string shape(const LoadedScene& loaded) const;
  // A hash of the problem the task builds (the scene file and the physics).
  static std::string problem(const LoadedScene& loaded);

 private:
  std::string kind_;
  std::map<std::string, std::string> texts_;  // the base scenes by path
};

}  // namespace keller
