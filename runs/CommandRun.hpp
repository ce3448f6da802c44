// The skeleton keller's commands share: load the scene, check the command line and the run's
// files, build the problem, run, publish; and the one failure path, run_command, through which
// every command that stops early says why, with its exit code (runs/ExitCode.hpp). A command
// (runs/SolveCommand, TraceCommand, EvolveCommand) is these phases with its own start and run
// between them; runs/ExportCommand shares the failure path.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/HeldFile.hpp"
#include "core/OutputLock.hpp"
#include "core/Problem.hpp"
#include "core/RunFiles.hpp"
#include "runs/BranchOutput.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/Interrupts.hpp"
#include "runs/OutputFile.hpp"
#include "runs/RunSummary.hpp"
#include "runs/SceneLoader.hpp"

namespace keller {

// Runs a command (`body`, which returns the exit code of a run that got to its end) with `summary`
// (a local one where null) reset: a CommandFailure it throws is reported (stderr, `summary`) and
// its code returned, any other error as one keller has no message for (CommandFailure::unexpected:
// exit 3 or 4). Only std::bad_alloc goes on, to the caller (keller's main says what it means).
int run_command(RunSummary* summary, const std::function<int(RunSummary&)>& body);

// Runs a step that reads the scene file `file` or builds its problem: a SceneError is bad input
// as it is (it names the file and the key), any other error bad input prefixed with `file`.
void reading_scene(const std::string& file, const std::function<void()>& step);
// Runs a step that checks the command line, the run's files or a stored start: any error is bad
// input as it is (its message names the flag, the path and the problem).
void checking(const std::function<void()>& step);

// The file of a command that writes its results point by point to OUT.h5.part (trace, evolve), as
// its messages name it.
struct RunFileKind {
  std::string what;       // its content: "branch", "time series"
  std::string file;       // the file (RunFiles): "branch file", "time-series file"
  std::string rows;       // its rows, counted: "rows", "steps"
  std::string row;        // one of them: "point", "step"
  std::string code_path;  // the dataset of its publication code: "/branch/exit_code"
  std::string short_of;   // where a failed run ends: "before its range"
  std::string ended;      // the signal point (core/SignalPoint) once it has ended: "traced"
};

class CommandRun {
 public:
  // `summary` receives what the run reports; `kind`: the file of a command that writes point by
  // point (write, publish, left).
  explicit CommandRun(RunSummary& summary, RunFileKind kind = {});
  CommandRun(const CommandRun&) = delete;
  CommandRun& operator=(const CommandRun&) = delete;

  // 1. Load: the scene file `scene` with the command's keys (`keys`) and `overrides`, its memory
  // estimate checked (check_memory); `options` reads the command's options from it (and throws
  // SceneError for a value it refuses). `output`: the output file (empty: SCENE_STEM.h5 here).
  void load(const std::string& scene, const std::string& output, const std::function<void(SceneSchema&)>& keys,
            const std::vector<std::string>& overrides, const std::function<void(const Scene&)>& options = {});
  // 2. Check: `declare` checks the command line (throwing std::invalid_argument with a message a
  // user can act on) and declares the run's files after the scene file (RunFiles: inputs that must
  // exist, outputs and temporaries that must be safe to write); then the output is locked (one run
  // at a time writes it; not where `locked`: the caller holds the lock, a study's task) and the
  // run says what it is (the scene's keys that differ from their defaults).
  void check(const std::function<void(RunFiles&)>& declare, bool locked = false);
  // 3. Build: the scene's problem; `refuse` throws (SceneError naming the key, or another error)
  // for what this command cannot run with it.
  Problem& build(const std::function<void(Problem&)>& refuse = {});

  // What an earlier run of this command left in OUT.h5.part (left_run: `record` the run's record,
  // `table` its rows and status; `fresh` discards it). Throws std::invalid_argument for an
  // unfinished run of another command.
  LeftRun left(const std::string& record, bool fresh, const UnfinishedTable& table) const;
  // 4. Run: the file's writer made by `open` (a File such as BranchFile, TimeSeriesFile: written(),
  // finish()) at OUT.h5.part; a file that cannot be made is exit 3, nothing written (any other
  // error bad input). `run` writes it point by point and says how the run ended; then the file is
  // ended and closed (write_run_file: an I/O error on the way is exit 3). SIGINT and SIGTERM stop
  // the run cleanly from here on (InterruptGuard).
  template <class File>
  RunEnd write(const std::function<std::unique_ptr<File>()>& open, const std::function<RunEnd(File&)>& run);
  // 5. Publish: an interrupted run stays in OUT.h5.part, to be continued (exit 130), and a failed
  // one never replaces an existing OUT.h5 (exit 1); else the file takes its name, with the fields
  // `fields` adds where the scene asks for them (publish_run). Returns the exit code.
  int publish(const RunEnd& end, const AddFields& fields);
  // The ended run that `left` found, killed before it took its name: published now.
  int publish_left(const LeftRun& left, const AddFields& fields);

  const LoadedScene& loaded() const { return loaded_; }
  const Scene& scene() const { return loaded_.scene; }
  const std::string& scene_file() const { return scene_file_; }
  const std::string& out() const { return out_; }
  const std::string& work() const { return work_; }  // OUT.h5.part
  bool with_fields() const { return with_fields_; }  // output.xdmf
  Problem& problem() { return *problem_; }
  RunSummary& summary() { return summary_; }

 private:
  // Makes the run's file by `open`: an IoError is exit 3 (nothing written), any other error bad input.
  void opening(const std::function<void()>& open);
  // The run's file written by `run` and ended by `finish` (write_run_file).
  RunEnd writing(const std::function<RunEnd()>& run, const std::function<void(std::optional<int>)>& finish);

  RunSummary& summary_;
  RunFileKind kind_;
  std::string scene_file_, out_, work_;
  LoadedScene loaded_;
  bool with_fields_ = false;
  OutputLock lock_;
  std::unique_ptr<Problem> problem_;
  std::optional<InterruptGuard> interrupts_;
  HeldFile written_;  // the file this run writes, to be published
};

template <class File>
RunEnd CommandRun::write(const std::function<std::unique_ptr<File>()>& open, const std::function<RunEnd(File&)>& run) {
  interrupts_.emplace();
  std::unique_ptr<File> file;
  opening([&] {
    file = open();
    written_ = std::move(file->written());
  });
  return writing([&] { return run(*file); }, [&](std::optional<int> code) { file->finish(code); });
}

}  // namespace keller
