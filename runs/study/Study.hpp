// A study: a family of ordinary runs (tasks) of one kind, trace, solve or orbit, made from a base scene
// by overrides of any scene keys: the product of the lists in [grid], the tables of [[cases]],
// or both (every case with every grid point), on top of [set]. Every task is validated like
// `--set` when the study is read, before any task runs, and no two tasks may resolve to the
// same run. Each task writes an ordinary output file under the study's folder, and a record of
// how it ended; the study is the sum of these.
//
//   [study]  scene = "base.toml" (relative to the study file), task = "trace" | "solve" | "orbit",
//            start = "FILE.h5:ROW" (optional: every task starts from that stored point; an orbit
//            task, `keller trace --orbit`, needs one: its located Hopf point, here or in its case)
//   [set]    "section.key" = value, ...           applied to every task
//   [grid]   "section.key" = [v1, v2, ...], ...   one task per combination
//   [[cases]] "section.key" = value, ...          one task per table ("scene" and "start" may vary too)
//   [collect] events = [...], stops = [...], end = [...]   what the collected table holds
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"

namespace keller {

struct StudyTask {
  int index = 0;
  std::string name;                                         // file name stem, stable under re-ordering
  std::string scene;                                        // base scene of this task
  std::string start;                                        // "FILE.h5:ROW" or ""
  std::vector<std::pair<std::string, std::string>> varied;  // the overrides that tell tasks apart (key, TOML value)
  std::vector<std::string> overrides;                       // every "key=value" applied to the scene
  // hashes, set when the task is checked: of its run record (what defines the run: the resolved
  // scene and start, Study::run_record), of what the names its output has depend on
  // (check_collect), and of the problem it builds (its size)
  std::string hash, shape, problem;
  std::string label() const;  // "fluid.model=fene-p, parameters.Gamma=0.000495"
};

// What defines a task's run, as its output stores it (/problem/run), and every key's default
// (records_agree: keys added to keller since).
struct TaskRunRecord {
  std::string record, defaults;
};

struct StudyCollect {
  std::vector<std::string> events;  // monitor names whose first located zero is collected, or fold, branch-point, hopf
  std::vector<std::string> stops;   // observables collected at every requested stop
  std::vector<std::string> end;     // observables collected at the last point
};

// The located kind a [collect] events name stands for: fold, bp or branch-point, hopf, pd or
// period-doubling, ns or neimark-sacker; nullopt for any other name (a monitor's zero).
std::optional<PointKind> collected_event_kind(const std::string& name);

class Study {
 public:
  // Reads and validates a study file: its keys, and every task's scene with its overrides
  // (like --set), or only task `only` (>= 0: the process that runs it). Throws SceneError naming
  // the file, the key and, for a task, the task; and for two tasks that resolve to the same run,
  // both. `folder`: where the tasks' files go ("" : <study stem> in the current directory).
  // Where there are many tasks, says on stderr that it checks them and what that took.
  static Study load(const std::string& path, const std::string& folder = "", int only = -1);
  // The names [collect] asks for, against what the tasks' outputs will hold (for a trace: the
  // branch table's columns, its problem's monitors and fold, branch-point, hopf for events; for a
  // solve: the problem's observables), before any task runs: one problem built per physics.
  // Throws SceneError naming the file, the key, the name and a task that lacks it.
  void check_collect() const;

  const std::string& path() const { return path_; }
  const std::string& name() const { return name_; }  // the study file's stem
  const std::string& kind() const { return kind_; }  // "trace", "solve" or "orbit"
  const std::string& folder() const { return folder_; }
  // Every task, by index; for a study loaded with `only`, that task alone.
  const std::vector<StudyTask>& tasks() const { return tasks_; }
  int task_count() const { return count_; }  // of the study file
  const StudyCollect& collect() const { return collect_; }
  std::vector<std::string> varied_keys() const;  // in the order of the study file
  // The task's run record, from its scene (a scene load: a study keeps only its hash).
  TaskRunRecord run_record(const StudyTask& t) const;
  // Whether a run record stored in an output agrees with the task's (records_agree; no scene
  // load where it is the same); where not, what differs goes to `difference`.
  bool record_agrees(const StudyTask& t, const std::string& stored, std::string* difference = nullptr) const;

  std::string task_output(const StudyTask& t) const;  // FOLDER/tasks/NAME.h5
  std::string task_log(const StudyTask& t) const;     // FOLDER/tasks/NAME.log
  std::string task_record(const StudyTask& t) const;  // FOLDER/tasks/NAME.toml
  std::string table_h5() const;                       // FOLDER/NAME.h5
  std::string table_csv() const;                      // FOLDER/NAME.csv

 private:
  void check_tasks();  // (load)
  std::string path_, name_, kind_, folder_;
  std::vector<StudyTask> tasks_;
  StudyCollect collect_;
  std::vector<std::string> varied_keys_;
  int count_ = 0;
};

}  // namespace keller
