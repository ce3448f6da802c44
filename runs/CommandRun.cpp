#include "runs/CommandRun.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <new>

#include "core/IoError.hpp"
#include "core/PendingFile.hpp"
#include "core/SignalPoint.hpp"

namespace keller {

int run_command(RunSummary* summary, const std::function<int(RunSummary&)>& body) {
  RunSummary local;
  RunSummary& s = summary ? *summary : local;
  s = {};
  try {
    return body(s);
  } catch (const CommandFailure& failure) {
    return failure.report(s);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    return CommandFailure::unexpected(e).report(s);
  }
}

void reading_scene(const std::string& file, const std::function<void()>& step) {
  try {
    step();
  } catch (const CommandFailure&) {
    throw;
  } catch (const SceneError& e) {
    throw CommandFailure::bad_input(e.what());
  } catch (const std::exception& e) {
    throw CommandFailure::bad_input(fmt::format("{}: {}", file, e.what()));
  }
}

void checking(const std::function<void()>& step) {
  try {
    step();
  } catch (const CommandFailure&) {
    throw;
  } catch (const std::exception& e) {
    throw CommandFailure::bad_input(e.what());
  }
}

CommandRun::CommandRun(RunSummary& summary, RunFileKind kind) : summary_(summary), kind_(std::move(kind)) {}

void CommandRun::load(const std::string& scene, const std::string& output,
                      const std::function<void(SceneSchema&)>& keys, const std::vector<std::string>& overrides,
                      const std::function<void(const Scene&)>& options) {
  scene_file_ = scene;
  reading_scene(scene, [&] {
    loaded_ = load_scene(scene, keys, overrides);
    check_memory(loaded_);
    if (options) options(loaded_.scene);
  });
  out_ = output.empty() ? std::filesystem::path(scene).stem().string() + ".h5" : output;
  work_ = PendingFile::temporary_for(out_);
  with_fields_ = loaded_.scene.boolean("output.xdmf");
}

void CommandRun::check(const std::function<void(RunFiles&)>& declare, bool locked) {
  checking([&] {
    RunFiles files;
    files.input("scene file", scene_file_);
    declare(files);
    files.check();
    if (!locked) lock_ = OutputLock(OutputLock::path_for(out_), "'" + out_ + "'");
  });
  fmt::print("{}\n", scene_summary(loaded_, out_));
}

Problem& CommandRun::build(const std::function<void(Problem&)>& refuse) {
  reading_scene(scene_file_, [&] {
    problem_ = loaded_.type->build(loaded_.scene);
    if (refuse) refuse(*problem_);
  });
  return *problem_;
}

LeftRun CommandRun::left(const std::string& record, bool fresh, const UnfinishedTable& table) const {
  return left_run(work_, record, loaded_.defaults(), fresh, kind_.what, kind_.rows, kind_.code_path, table);
}

void CommandRun::opening(const std::function<void()>& open) {
  try {
    open();
  } catch (const IoError& e) {
    throw CommandFailure::io_failure(fmt::format("{}; nothing written", e.what()));
  } catch (const std::exception& e) {
    throw CommandFailure::bad_input(e.what());
  }
}

RunEnd CommandRun::writing(const std::function<RunEnd()>& run, const std::function<void(std::optional<int>)>& finish) {
  return write_run_file(work_, out_, written_, kind_.what, kind_.row, run, finish);
}

int CommandRun::publish(const RunEnd& end, const AddFields& fields) {
  if (const auto stays =
          stays_unfinished(end.interrupted, end.failed, work_, out_, kind_.what, kind_.short_of, summary_))
    return *stays;
  const int code = summary_.exit_code;
  signal_point(kind_.ended);
  return publish_run(work_, out_, with_fields_, fields, written_, code, kind_.what, summary_);
}

int CommandRun::publish_left(const LeftRun& left, const AddFields& fields) {
  return publish_left_run(work_, out_, with_fields_, fields, left, kind_.what, summary_);
}

}  // namespace keller
