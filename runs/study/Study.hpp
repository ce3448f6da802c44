// A study: a family of ordinary runs (tasks) of one kind, trace or solve, made from a base scene
// by overrides of any scene keys: the product of the lists in [grid], the tables of [[cases]],
// or both (every case with every grid point), on top of [set]. Every task is validated like
// `--set` when the study is read, before any task runs. Each task writes an ordinary output
// file under the study's folder, and a record of how it ended; the study is the sum of these.
//
//   [study]  scene = "base.toml" (relative to the study file), task = "trace" | "solve",
//            start = "FILE.h5:ROW" (optional: every task starts from that stored point)
//   [set]    "section.key" = value, ...           applied to every task
//   [grid]   "section.key" = [v1, v2, ...], ...   one task per combination
//   [[cases]] "section.key" = value, ...          one task per table ("scene" and "start" may vary too)
//   [collect] events = [...], stops = [...], end = [...]   what the collected table holds
#pragma once

#include <map>
#include <string>
#include <vector>

namespace keller {

struct StudyTask {
  int index = 0;
  std::string name;                                         // file name stem, stable under re-ordering
  std::string scene;                                        // base scene of this task
  std::string start;                                        // "FILE.h5:ROW" or ""
  std::vector<std::pair<std::string, std::string>> varied;  // the overrides that tell tasks apart (key, TOML value)
  std::vector<std::string> overrides;                       // every "key=value" applied to the scene
  std::string record;                                       // what defines the run (resolved scene, start, kind)
  std::string hash;                                         // of the record (task_current)
  std::string defaults;                                     // every key's default (records_agree)
  std::string label() const;                                // "fluid.model=fene-p, parameters.Gamma=0.000495"
};

struct StudyCollect {
  std::vector<std::string> events;  // monitor names whose first located zero is collected, or fold, branch-point, hopf
  std::vector<std::string> stops;   // observables collected at every requested stop
  std::vector<std::string> end;     // observables collected at the last point
};

class Study {
 public:
  // Reads and validates a study file: its keys, and every task's scene with its overrides
  // (like --set). Throws SceneError naming the file, the key and, for a task, the task.
  // `folder`: where the tasks' files go ("" : <study stem> in the current directory).
  static Study load(const std::string& path, const std::string& folder = "");
  // The names [collect] asks for, against what the tasks' outputs will hold (for a trace: the
  // branch table's columns, its problem's monitors and fold, branch-point, hopf for events; for a
  // solve: the problem's observables), before any task runs: one problem built per physics.
  // Throws SceneError naming the file, the key, the name and a task that lacks it.
  void check_collect() const;

  const std::string& path() const { return path_; }
  const std::string& name() const { return name_; }  // the study file's stem
  const std::string& kind() const { return kind_; }  // "trace" or "solve"
  const std::string& folder() const { return folder_; }
  const std::vector<StudyTask>& tasks() const { return tasks_; }
  const StudyCollect& collect() const { return collect_; }
  std::vector<std::string> varied_keys() const;  // in the order of the study file

  std::string task_output(const StudyTask& t) const;  // FOLDER/tasks/NAME.h5
  std::string task_log(const StudyTask& t) const;     // FOLDER/tasks/NAME.log
  std::string task_record(const StudyTask& t) const;  // FOLDER/tasks/NAME.toml
  std::string table_h5() const;                       // FOLDER/NAME.h5
  std::string table_csv() const;                      // FOLDER/NAME.csv

 private:
  std::string path_, name_, kind_, folder_;
  std::vector<StudyTask> tasks_;
  StudyCollect collect_;
  std::vector<std::string> varied_keys_;
};

}  // namespace keller
