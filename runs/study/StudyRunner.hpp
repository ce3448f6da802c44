// Running a study's tasks: each in its own process (`keller study run STUDY --task K`), so that a
// task that crashes costs that task only. The local executor keeps `jobs` of them running on
// this machine; the MPI executor (StudyMpi) gives them to the ranks of an mpirun. Both run the
// tasks that are not done, longest expected first, print a line per finished task with what it
// found, how many are done and left and an estimate of the time left, and end by collecting the
// table. A worker that dies is run once more, then recorded as failed; the study goes on.
#pragma once

#include <sys/types.h>

#include <functional>
#include <string>
#include <vector>

#include "core/OutputLock.hpp"
#include "runs/study/Study.hpp"
#include "runs/study/StudyTask.hpp"

namespace keller {

// Starts the task's process with its output in the task's log, `blas_threads` BLAS threads, and
// SIGTERM if this process dies (the task then stops after its current point, to be continued).
pid_t spawn_task(const Study& study, const StudyTask& task, int blas_threads);
// The program a task's process runs: this one (/proc/self/exe) unless set, as a process that runs
// keller's commands but is not a keller program sets it (the Python package: the keller program).
void set_task_program(std::string path);
// The record the finished task process `pid` left; `status` is waitpid's. A process that left no
// record of its own for the task's hash died: the record says so (status "died").
TaskRecord finished_task(const Study& study, const StudyTask& task, pid_t pid, int status);

// Whether a task's process ended by SIGTERM or SIGINT (waitpid's status): one that a signal to
// the study stopped before its run took signals.
bool stopped_by_signal(int status);

// The tasks to run (not done), longest expected first: by the time the task took before, else
// by the size of its problem.
std::vector<int> tasks_to_run(const Study& study);

// One line per finished task, with the time left estimated from the tasks finished so far.
class StudyProgress {
 public:
  StudyProgress(const Study& study, int to_run, int workers);
  void finished(const StudyTask& task, const TaskRecord& record);

 private:
  const Study& study_;
  int total_, done_ = 0, workers_;
  double start_;
};

// The BLAS threads a worker gets when `workers` share this machine's cores.
int blas_threads_for(int workers);
// The same from its inputs: cores / workers, at least 1, and at most a positive OPENBLAS_NUM_THREADS
// the user set (`user`, null or not a positive integer: none), so that a user who limits BLAS on
// a shared machine keeps that limit in every task.
int blas_threads_for(int workers, int cores, const char* user);

// Runs the study here with `jobs` worker processes. Exit codes: 0 every task done, 1 some task
// failed, 3 a task's record or the table could not be written (no task is started after it), 130
// interrupted: by SIGINT or SIGTERM, which it passes on to the tasks' processes (they stop after
// their current point and are continued by the next run of the study), or a task was.
int run_study_local(const Study& study, int jobs);
// Under mpirun: rank 0 schedules, the other ranks run tasks. Returns the exit code of rank 0's
// study (the same for every rank).
int run_study_mpi(const Study& study, int& argc, char**& argv);
// Whether this process was started by mpirun (and keller was built with MPI).
bool under_mpi();

// Prints the scheduling overhead: the mean gap between the end of a task on a worker and the
// start of its next one, against the mean time of a task's process.
void print_overhead(int gaps, double gap_seconds, int tasks, double process_seconds);

// Writes the collected table (FOLDER/NAME.csv and .h5) and prints where; false (saying why on
// stderr) where it cannot be written.
bool write_study_table(const Study& study);
// Writes a finished task's record; false (saying why on stderr) where it cannot be written.
bool save_task_record(const Study& study, const StudyTask& task, const TaskRecord& record);

// The study's folder made ready and held by this process (rank 0 under MPI) while the study runs
// or is collected: a folder (made where missing) with its tasks/ folder, and the lock
// FOLDER/study.lock, so that a second study on the folder is refused at its start, naming this
// one. Throws std::invalid_argument for a path that cannot be the folder, OutputLocked where
// another process holds it.
OutputLock hold_study_folder(const Study& study);

}  // namespace keller
