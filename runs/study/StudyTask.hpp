// One task of a study, run in this process: an ordinary trace or solve whose output goes to
// FOLDER/tasks/NAME.h5, followed by the task's record FOLDER/tasks/NAME.toml (how it ended and
// what it cost, with the hash of what defined it). A task is done when its record says so for
// the task's current hash and its output is there; a rerun of the study runs every other task
// again (missing, failed, interrupted, or changed by the study file or the base scene).
#pragma once

#include <optional>
#include <string>

#include "runs/RunSummary.hpp"
#include "runs/study/Study.hpp"

namespace keller {

struct TaskRecord {
  std::string hash;            // StudyTask::hash when it ran
  std::string status;          // "done", "failed" or "interrupted"
  RunSummary summary;          // exit code, why it ended, the output, the cost
  int attempts = 1;            // runs of this task by the executor (a worker that died is retried once)
  double process_seconds = 0;  // the task's process from start to end, as its executor saw it
  double peak_mb = 0;          // the task process's peak resident memory
};

// Runs the task (continuing its unfinished output if a run of it was interrupted; removing an
// output left by another version of it), writes its record and returns it. Never throws for a
// failure of the task: that is a record with status "failed" and its reason.
TaskRecord run_study_task(const Study& study, const StudyTask& task);

// The task's record, if it has one that can be read.
std::optional<TaskRecord> read_task_record(const Study& study, const StudyTask& task);
// Writes a record atomically.
void write_task_record(const Study& study, const StudyTask& task, const TaskRecord& record);
// Whether a record belongs to the task as it is now: the same hash, or an output whose run record
// agrees with the task's (records_agree: keys added to keller since, at their defaults, are no
// change).
bool task_current(const Study& study, const StudyTask& task, const TaskRecord& record);
// Done as the task is now, with its output in place.
bool task_done(const Study& study, const StudyTask& task);

}  // namespace keller
