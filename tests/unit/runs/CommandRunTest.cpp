// The skeleton the commands share (runs/CommandRun): the one failure path (run_command), the
// phases' errors as exit codes (load, check and build: bad input naming the file, key or path),
// and the point-by-point file of trace and evolve (written, published, or kept where a signal or a
// failure ends the run), on a scene written by the test and a branch of the cubic problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <new>

#include "continuation/output/BranchFile.hpp"
#include "core/IoError.hpp"
#include "runs/CommandRun.hpp"
#include "runs/ExitCode.hpp"
#include "runs/TraceCommand.hpp"
#include "support/TestProblems.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

const RunFileKind kBranch{"branch", "branch file", "rows", "point", "/branch/exit_code", "before its range", "traced"};

// A bratu1d scene file in `dir`, its [continuation] and [output] as given.
std::string scene_file(const std::string& dir, const std::string& extra = "") {
  const std::string path = dir + "/scene.toml";
  std::ofstream(path) << "[problem]\ntype = \"bratu1d\"\n[bratu]\nintervals = 8\n[continuation]\nparameter = "
                         "\"lambda\"\n[output]\nxdmf = false\n"
                      << extra;
  return path;
}

// run_command with its stderr captured (returned in `err`).
int run_quietly(RunSummary* summary, const std::function<int(RunSummary&)>& body, std::string& err) {
  testing::internal::CaptureStderr();
  const int code = run_command(summary, body);
  err = testing::internal::GetCapturedStderr();
  return code;
}

// The cubic's branch from lambda = -1 to 1, written through CommandRun::write and ended as `end` says.
RunEnd write_branch(CommandRun& run, const RunEnd& end) {
  test::CubicProblem problem(-1.0);
  ContinuationOptions o;
  o.parameter = "lambda";
  o.stop.upper = 1.0;
  o.state_scale = 1.0;
  Continuation stepper(problem, o);
  testing::internal::CaptureStdout();
  const RunEnd ended = run.write<BranchFile>(
      [&] {
        return std::make_unique<BranchFile>(run.work(), problem, o, stepper.monitor_names(), 1.0,
                                            [](H5File& f) { f.write_string("/problem/run", "test"); });
      },
      [&](BranchFile& file) {
        stepper.run(Vector::Constant(1, -2.0), file);
        return end;
      });
  testing::internal::GetCapturedStdout();
  return ended;
}

}  // namespace

// The body's code where it gets to its end, the summary reset before it.
TEST(CommandRun, ACommandThatEndsReturnsItsCode) {
  RunSummary summary;
  summary.reason = "an earlier run's";
  std::string err;
  EXPECT_EQ(run_quietly(
                &summary, [](RunSummary& s) { return s.reason.empty() ? 0 : 9; }, err),
            0);
  EXPECT_EQ(err, "");
  EXPECT_EQ(run_quietly(
                nullptr, [](RunSummary&) { return exit_code::interrupted; }, err),
            exit_code::interrupted);
}

// The one failure path: a CommandFailure is reported with its code; any other error is one keller
// has no message for (exit 3 for a file, 4 for a defect); std::bad_alloc goes on to main.
TEST(CommandRun, EveryFailureIsReportedInOnePlace) {
  RunSummary summary;
  std::string err;
  int code = run_quietly(
      &summary,
      [](RunSummary&) -> int { throw CommandFailure::bad_input("--restart and --switch exclude each other"); }, err);
  EXPECT_EQ(code, exit_code::usage);
  EXPECT_EQ(err, "keller: error: --restart and --switch exclude each other\n");
  EXPECT_EQ(summary.exit_code, exit_code::usage);
  EXPECT_EQ(summary.reason, "--restart and --switch exclude each other");
  code = run_quietly(
      &summary, [](RunSummary&) -> int { throw IoError("cannot write 'a.h5'"); }, err);
  EXPECT_EQ(code, exit_code::io_failure);
  EXPECT_EQ(err, "keller: error: cannot write 'a.h5'\n");
  code = run_quietly(
      &summary, [](RunSummary&) -> int { throw std::logic_error("boom"); }, err);
  EXPECT_EQ(code, exit_code::internal_error);
  EXPECT_EQ(err.rfind("keller: internal error: boom; this is a defect of keller", 0), 0u) << err;
  EXPECT_EQ(summary.exit_code, exit_code::internal_error);
  EXPECT_THROW(run_command(&summary, [](RunSummary&) -> int { throw std::bad_alloc(); }), std::bad_alloc);
}

// A step that reads the scene: its SceneError as it is, another error prefixed with the file; a
// step that checks: its error as it is; a CommandFailure passes both unchanged.
TEST(CommandRun, StepsMapTheirErrorsToBadInput) {
  auto reason_of = [](const std::function<void()>& step) {
    try {
      step();
    } catch (const CommandFailure& f) {
      EXPECT_EQ(f.code(), exit_code::usage);
      return f.reason();
    }
    return std::string("no failure");
  };
  EXPECT_EQ(reason_of([] { reading_scene("s.toml", [] { throw SceneError("s.toml: key 'a.b': unknown key"); }); }),
            "s.toml: key 'a.b': unknown key");
  EXPECT_EQ(reason_of([] { reading_scene("s.toml", [] { throw std::invalid_argument("no mesh"); }); }),
            "s.toml: no mesh");
  EXPECT_EQ(reason_of([] { checking([] { throw std::invalid_argument("--free applies to a curve"); }); }),
            "--free applies to a curve");
  EXPECT_EQ(reason_of([] { checking([] { throw CommandFailure::bad_input("as it was"); }); }), "as it was");
  try {
    reading_scene("s.toml", [] { throw CommandFailure::io_failure("disk full"); });
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::io_failure);
  }
}

// Load: the output defaults to SCENE_STEM.h5, written as OUT.h5.part; a key the scene may not
// have, or a value the command's options refuse, is bad input naming the file and the key.
TEST(CommandRun, LoadReadsTheSceneAndRefusesBadKeys) {
  const std::string dir = test::scratch_dir("command_run_load");
  const std::string scene = scene_file(dir);
  RunSummary summary;
  CommandRun run(summary, kBranch);
  run.load(scene, "", declare_trace_keys, {"bratu.intervals=4"});
  EXPECT_EQ(run.out(), "scene.h5");
  EXPECT_EQ(run.work(), "scene.h5.part");
  EXPECT_FALSE(run.with_fields());
  EXPECT_EQ(run.scene().integer("bratu.intervals"), 4);
  CommandRun other(summary);
  try {
    other.load(scene, "x.h5", declare_trace_keys, {"continuation.no_such_key=1"});
    ADD_FAILURE() << "not refused";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::usage);
    EXPECT_NE(f.reason().find(scene), std::string::npos) << f.reason();
    EXPECT_NE(f.reason().find("continuation.no_such_key"), std::string::npos) << f.reason();
  }
  try {
    other.load(scene, "x.h5", declare_trace_keys, {},
               [](const Scene& s) { throw s.error("continuation.parameter", "not this one"); });
    ADD_FAILURE() << "not refused";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::usage);
    EXPECT_NE(f.reason().find("not this one"), std::string::npos) << f.reason();
  }
}

// Check: the command line's refusals and unsafe outputs are bad input; the output is locked, so a
// second run on it is refused while the first holds it (unless the caller holds the lock); the
// run then says what it is.
TEST(CommandRun, CheckRefusesBadFilesAndLocksTheOutput) {
  const std::string dir = test::scratch_dir("command_run_check");
  const std::string scene = scene_file(dir);
  RunSummary summary;
  auto loaded = [&](CommandRun& run, const std::string& out) { run.load(scene, out, declare_trace_keys, {}); };
  CommandRun refused(summary);
  loaded(refused, dir + "/a.h5");
  EXPECT_THROW(refused.check([](RunFiles&) { throw std::invalid_argument("--force applies to a start"); }),
               CommandFailure);
  CommandRun missing(summary);
  loaded(missing, dir + "/no/such/folder/a.h5");
  EXPECT_THROW(missing.check([&](RunFiles& files) { files.output("branch file", missing.out()); }), CommandFailure);

  CommandRun first(summary);
  loaded(first, dir + "/a.h5");
  testing::internal::CaptureStdout();
  first.check([&](RunFiles& files) { declare_run_outputs(files, first.out(), "branch file", false); });
  const std::string said = testing::internal::GetCapturedStdout();
  EXPECT_NE(said.find("# every key, with its default: keller info " + dir + "/a.h5 --scene"), std::string::npos)
      << said;
  EXPECT_TRUE(fs::exists(dir + "/a.h5.lock"));
  CommandRun second(summary);
  loaded(second, dir + "/a.h5");
  try {
    second.check([](RunFiles&) {});
    ADD_FAILURE() << "not refused";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::usage);
    EXPECT_NE(f.reason().find(dir + "/a.h5"), std::string::npos) << f.reason();
  }
  CommandRun study_task(summary);
  loaded(study_task, dir + "/a.h5");
  testing::internal::CaptureStdout();
  EXPECT_NO_THROW(study_task.check([](RunFiles&) {}, true));
  testing::internal::GetCapturedStdout();
}

// Build: the scene's problem, or bad input where the command refuses it.
TEST(CommandRun, BuildMakesTheScenesProblem) {
  const std::string dir = test::scratch_dir("command_run_build");
  RunSummary summary;
  CommandRun run(summary);
  run.load(scene_file(dir), "", declare_trace_keys, {});
  EXPECT_EQ(run.build().size(), 7);  // 8 intervals, the ends fixed
  CommandRun refused(summary);
  refused.load(scene_file(dir), "", declare_trace_keys, {});
  try {
    refused.build([&](Problem&) { throw refused.scene().error("continuation.parameter", "unknown parameter 'nu'"); });
    ADD_FAILURE() << "not refused";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::usage);
    EXPECT_NE(f.reason().find("unknown parameter 'nu'"), std::string::npos) << f.reason();
  }
}

// Write and publish: a run that ends takes its name (OUT.h5.part gone); an interrupted one stays in
// OUT.h5.part (exit 130); a failed one does not replace an existing OUT.h5 (exit 1); a file that
// cannot be made is exit 3, nothing written.
TEST(CommandRun, TheRunsFileTakesItsNameOnlyWhenItEnded) {
  const std::string dir = test::scratch_dir("command_run_write");
  const std::string scene = scene_file(dir);
  RunSummary summary;
  const AddFields none;
  auto published = [&](const std::string& out, const RunEnd& end) {
    CommandRun run(summary, kBranch);
    run.load(scene, out, declare_trace_keys, {});
    const RunEnd ended = write_branch(run, end);
    testing::internal::CaptureStdout();
    const int code = run.publish(ended, none);
    testing::internal::GetCapturedStdout();
    return code;
  };
  EXPECT_EQ(published(dir + "/ok.h5", {}), exit_code::ok);
  EXPECT_TRUE(fs::exists(dir + "/ok.h5"));
  EXPECT_FALSE(fs::exists(dir + "/ok.h5.part"));
  EXPECT_EQ(summary.output, dir + "/ok.h5");
  EXPECT_EQ(published(dir + "/int.h5", {true, false}), exit_code::interrupted);
  EXPECT_FALSE(fs::exists(dir + "/int.h5"));
  EXPECT_TRUE(fs::exists(dir + "/int.h5.part"));
  const auto before = fs::last_write_time(dir + "/ok.h5");
  EXPECT_EQ(published(dir + "/ok.h5", {false, true}), exit_code::numerical_failure);
  EXPECT_EQ(fs::last_write_time(dir + "/ok.h5"), before);
  EXPECT_TRUE(fs::exists(dir + "/ok.h5.part"));

  CommandRun run(summary, kBranch);
  run.load(scene, dir + "/io.h5", declare_trace_keys, {});
  try {
    run.write<BranchFile>([]() -> std::unique_ptr<BranchFile> { throw IoError("disk full"); },
                          [](BranchFile&) { return RunEnd{}; });
    ADD_FAILURE() << "no failure";
  } catch (const CommandFailure& f) {
    EXPECT_EQ(f.code(), exit_code::io_failure);
    EXPECT_EQ(f.reason(), "disk full; nothing written");
  }
}
