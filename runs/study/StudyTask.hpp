// One task of a study, run in this process: an ordinary trace or solve whose output goes to
// FOLDER/tasks/NAME.h5, followed by the task's record FOLDER/tasks/NAME.toml (how it ended and
// what it cost, with the hash of what defined it). A task is done when its record says so for
// the task's current hash and its own output is there; a rerun of the study runs every other
// task again (missing, failed, interrupted, damaged, or changed by the study file or the base
// scene).
#pragma once

#include <optional>
#include <string>

#include "core/OutputLock.hpp"
#include "runs/RunSummary.hpp"
#include "runs/study/Study.hpp"

namespace keller {

struct TaskRecord {
  std::string hash;            // StudyTask::hash when it ran
  std::string status;          // "done", "failed" or "interrupted"
  RunSummary summary;          // exit code, why it ended, the output, the cost
  int attempts = 1;            // runs of this task by the executor (a worker that died is retried once)
  double process_seconds = 0;  // its processes, start to end, as its executor saw them (every run in its output)
  double peak_mb = 0;          // the task process's peak resident memory
  long pid = 0;                // the process that ran it (tells its record from an earlier run's)
};

// Runs the task (continuing its unfinished output if a run of it was interrupted, and adding its
// cost to theirs; setting aside an output or unfinished run that is not its own), writes its
// record and returns it. Never throws for a failure of the task: that is a record with status
// "failed" and its reason. A task whose output another process holds (hold_task_output: it runs
// the task) is left to it, touching nothing of it: recorded "interrupted", saying so, unless that
// process has finished it meanwhile.
TaskRecord run_study_task(const Study& study, const StudyTask& task);

// The task's record, if it has one that can be read.
std::optional<TaskRecord> read_task_record(const Study& study, const StudyTask& task);
// Writes a record atomically.
void write_task_record(const Study& study, const StudyTask& task, const TaskRecord& record);
// Whether a record belongs to the task as it is now: the same hash, or an output whose run record
// agrees with the task's (records_agree: keys added to keller since, at their defaults, are no
// change).
bool task_current(const Study& study, const StudyTask& task, const TaskRecord& record);
// The record of the task's interrupted runs (their cost together), where it has one for the
// task as it is now: what a run that continues their output adds its own to.
std::optional<TaskRecord> interrupted_record(const Study& study, const StudyTask& task);
// Done as the task is now, with its own output in place (output_fault finds nothing).
bool task_done(const Study& study, const StudyTask& task);

// What keeps the file at `path` (the task's output) from being the task's own complete output,
// for people ("is missing", "cannot be read as an HDF5 file", "holds another run (it differs in:
// bratu.intervals = 128 in the file, 48 in this scene)"); empty where nothing does: a readable
// file whose run record (/problem/run) agrees with the task's and whose results can be read.
std::string output_fault(const Study& study, const StudyTask& task, const std::string& path);
// Takes the lock of the task's output (OUT.h5.lock, core/OutputLock): what holds it is the one
// process that runs the task. Throws OutputLocked naming the process that holds it.
OutputLock hold_task_output(const Study& study, const StudyTask& task);
// Moves what is not the task's own out of its way, to FOLDER/set_aside/ (the first free name
// STEM-N.EXT), saying so on the terminal: an output with an output_fault, and an unfinished run
// (OUT.h5.part) that is not the task's to continue. The caller holds the task's output lock
// (`held`, hold_task_output), so that no running process has its files moved. Nothing is
// deleted. Throws IoError naming the file where it cannot be moved.
void set_aside_foreign_outputs(const Study& study, const StudyTask& task, const OutputLock& held);

}  // namespace keller
