#include "runs/study/StudyCommand.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <thread>

#include "core/Scene.hpp"
#include "runs/ExitCode.hpp"
#include "runs/study/Study.hpp"
#include "runs/study/StudyRunner.hpp"
#include "runs/study/StudyTable.hpp"
#include "runs/study/StudyTask.hpp"

namespace keller {

int run_study_command(const StudyArguments& args, int& argc, char**& argv) {
  Study study;
  try {
    // the process that runs one task checks that task alone (its study checked them all)
    study = Study::load(args.study, args.folder, args.action == "run" ? std::max(args.task, 0) : -1);
  } catch (const SceneError& e) {
    fmt::print(stderr, "keller: error: {}\n", e.what());
    return exit_code::usage;
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: {}: {}\n", args.study, e.what());
    return exit_code::usage;
  }
  if (args.action == "list") {
    fmt::print("# {} tasks of {} (task, status, name, overrides); folder {}/\n", study.tasks().size(), study.path(),
               study.folder());
    for (const StudyTask& t : study.tasks()) {
      const StudyRow row = StudyTable::row(study, t);
      fmt::print("{} {} {} {}\n", t.index, row.text.at("status"), t.name, t.label());
    }
    return exit_code::ok;
  }
  if (args.action == "run") {
    if (args.task < 0 || args.task >= study.task_count()) {
      fmt::print(stderr, "keller: error: {}: --task {} does not exist (tasks 0 to {})\n", args.study, args.task,
                 study.task_count() - 1);
      return exit_code::usage;
    }
    try {
      const TaskRecord r = run_study_task(study, study.tasks().front());
      return r.status == "done"          ? exit_code::ok
             : r.status == "interrupted" ? exit_code::interrupted
                                         : exit_code::numerical_failure;
    } catch (const std::exception& e) {  // its record or its folder cannot be written
      RunSummary unrecorded;
      return fail_unexpected(unrecorded, e, fmt::format("task {} of {} has no record", args.task, args.study));
    }
  }
  // what [collect] names, against the tasks' problems: before any task runs (or a table of
  // nothing after all of them)
  try {
    study.check_collect();
  } catch (const SceneError& e) {
    fmt::print(stderr, "keller: error: {}\n", e.what());
    return exit_code::usage;
  }
  const bool collect = args.action == "collect";
  if (!collect && under_mpi()) return run_study_mpi(study, argc, argv);  // rank 0 holds the folder
  OutputLock folder;  // the study's folder is this process's while it runs or is collected
  try {
    folder = hold_study_folder(study);
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: {}\n", e.what());
    return exit_code::usage;
  }
  if (collect) return write_study_table(study) ? exit_code::ok : exit_code::io_failure;
  const int jobs = args.jobs > 0 ? args.jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return run_study_local(study, jobs);
}

}  // namespace keller
