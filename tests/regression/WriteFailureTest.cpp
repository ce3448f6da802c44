// Issue 30, item 8, through the real driver: a write that fails (a file-size limit, a full
// device) ends the command with exit code 3 and a message naming the file and the system's
// reason, never with a crash; what was completed is kept (a trace's points in OUT.h5.part, which
// the same command continues), and nothing half-written takes an output's name. A study's folder
// that cannot be one is refused at the start with exit code 2.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "continuation/output/BranchFile.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

const std::string bratu1d = test::source_path("runs/scenes/bratu1d_fold.toml");
const std::string bratu2d = test::source_path("runs/scenes/bratu2d_fold.toml");

// The shell prefix that limits the size of every file keller writes to `kb` KiB (/bin/sh counts
// 512-byte blocks) and lets a write beyond it fail with EFBIG instead of killing the process.
std::string file_size_limit(int kb) { return "trap '' XFSZ; ulimit -f " + std::to_string(2 * kb) + ";"; }

void expect_io_failure(const test::CommandResult& r, const std::string& file, const std::string& reason) {
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_NE(r.err.find("keller: error:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
}

}  // namespace

// A branch whose file outgrows the limit midway: exit 3 naming OUT.h5.part, every point before the
// failure readable there, and the same command without the limit continues it to the whole
// branch. Under a limit that the file's header already exceeds nothing is left at all.
TEST(WriteFailure, ATraceThatCannotWriteStopsKeepingItsPoints) {
  const std::string dir = test::scratch_dir("write_trace");
  const std::string command =
      "trace " + bratu2d + " --set bratu.intervals=32 --set continuation.save_every=1 -o " + dir + "/c.h5";
  auto r = test::run_keller(command, file_size_limit(600));
  expect_io_failure(r, dir + "/c.h5.part", "File too large");
  EXPECT_NE(r.err.find("run the same command again to continue"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/c.h5"));
  const BranchTable kept = read_branch_table(dir + "/c.h5.part");
  EXPECT_GE(kept.rows.rows(), 5);
  EXPECT_TRUE(kept.rows.allFinite());
  r = test::run_keller(command);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("continuing the unfinished branch"), std::string::npos) << r.out;
  EXPECT_GT(read_branch_table(dir + "/c.h5").rows.rows(), kept.rows.rows());

  r = test::run_keller(command + "2", file_size_limit(32));
  expect_io_failure(r, dir + "/c.h52.part", "File too large");
  for (const char* left : {"/c.h52", "/c.h52.part", "/c.h52.part.part"}) EXPECT_FALSE(fs::exists(dir + left)) << left;
}

// solve and evolve under a limit: exit 3 naming the file, no output and no temporary left.
TEST(WriteFailure, SolveAndEvolveThatCannotWriteStopWithCode3) {
  const std::string dir = test::scratch_dir("write_solve");
  auto r = test::run_keller("solve " + bratu2d + " --set bratu.intervals=32 -o " + dir + "/s.h5", file_size_limit(16));
  expect_io_failure(r, dir + "/s.h5.part", "File too large");
  for (const char* left : {"/s.h5", "/s.h5.part", "/s.xdmf"}) EXPECT_FALSE(fs::exists(dir + left)) << left;
  r = test::run_keller("evolve " + test::source_path("runs/scenes/brusselator1d_evolve.toml") +
                           " --set evolve.t_end=10 --set evolve.print_every=1000 -o " + dir + "/e.h5",
                       file_size_limit(48));
  expect_io_failure(r, dir + "/e.h5.part", "File too large");
  EXPECT_FALSE(fs::exists(dir + "/e.h5"));
}

// The table to a full device: exit 3, not 0 with part of it written.
TEST(WriteFailure, ExportToAFullDeviceStopsWithCode3) {
  const std::string dir = test::scratch_dir("write_export");
  auto r = test::run_keller("trace " + bratu1d + " --set bratu.intervals=40 -o " + dir + "/b1.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_keller("export " + dir + "/b1.h5 --csv - >/dev/full");
  expect_io_failure(r, "the standard output", "No space left on device");
}

// Exit code 3 is a file that could not be written or kept, and nothing else: an error keller has
// no message of its own for (a defect of keller; KELLER_SIGNAL=THROW stands for one) ends the
// command with exit code 4, asking for a report, whether it comes while the branch is traced (the
// driver's last resort) or while its fields are written (the branch stays in OUT.h5.part). Either
// way the same command then finishes the branch: the rows of the branch traced without a stop.
TEST(WriteFailure, AnErrorThatIsNoWriteFailureIsAnInternalError) {
  const std::string dir = test::scratch_dir("write_internal");
  const std::string options =
      " --set bratu.intervals=8 --set continuation.save_every=2 --set continuation.max_step=0.2 -o ";
  const std::string command = "trace " + bratu2d + options + dir + "/c.h5";
  auto whole = test::run_keller("trace " + bratu2d + options + dir + "/whole.h5");
  ASSERT_EQ(whole.exit_code, 0) << whole.out << whole.err;
  const BranchTable uninterrupted = read_branch_table(dir + "/whole.h5");
  const Eigen::VectorXd lambdas = uninterrupted.rows.col(uninterrupted.column(uninterrupted.parameter));
  ASSERT_GT(lambdas.size(), 40);  // (past the fold and back: both stops fall within it)
  for (const std::string at : {"point:3", "fields:2"}) {
    SCOPED_TRACE(at);
    fs::remove(dir + "/c.h5");
    auto r = test::run_keller(command, "KELLER_SIGNAL_AT=" + at + " KELLER_SIGNAL=THROW");
    EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
    EXPECT_NE(r.err.find("keller: internal error: KELLER_SIGNAL=THROW at " + at.substr(0, at.find(':'))),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("please report it"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/c.h5"));
    ASSERT_TRUE(fs::exists(dir + "/c.h5.part"));
    if (at == "fields:2") {
      EXPECT_NE(r.err.find("the branch stays in " + dir + "/c.h5.part"), std::string::npos) << r.err;
    }
    r = test::run_keller(command);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    // the same steps from the stored point on: the same rows, their parameter values to the
    // corrector's tolerance (the iterates after a restart start on a factorisation of their own)
    const BranchTable finished = read_branch_table(dir + "/c.h5");
    ASSERT_EQ(finished.rows.rows(), lambdas.size());
    EXPECT_LT((finished.rows.col(finished.column(finished.parameter)) - lambdas).cwiseAbs().maxCoeff(), 1e-6);
  }
}

// A study whose folder cannot be one is refused at the start; a study whose records cannot be
// written stops with code 3 and a message, never with a crash.
TEST(WriteFailure, AStudyWithoutAWritableFolderStopsWithAMessage) {
  const std::string dir = test::scratch_dir("write_study");
  const std::string study = dir + "/s.toml";
  std::ofstream(study) << "[study]\nscene = \"" << bratu1d
                       << "\"\n\n[set]\n\"output.xdmf\" = false\n\n[grid]\n\"bratu.intervals\" = [16, 24]\n";
  std::ofstream(dir + "/afile") << "mine\n";
  fs::create_directories(dir + "/t");
  std::ofstream(dir + "/t/tasks") << "mine\n";
  const struct {
    std::string folder, expected;
  } refused[] = {
      {dir + "/afile", "'" + dir + "/afile' is not a folder"},
      {dir + "/afile/sub", "'" + dir + "/afile/sub' cannot be made"},
      {dir + "/t", "'" + dir + "/t/tasks' is not a folder"},
  };
  for (const auto& c : refused) {
    SCOPED_TRACE(c.folder);
    const auto r = test::run_keller("study " + study + " --jobs 1 -o " + c.folder);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
  }
  EXPECT_TRUE(test::file_contents(dir + "/afile") == "mine\n") << "changed";
  EXPECT_TRUE(test::file_contents(dir + "/t/tasks") == "mine\n") << "changed";
  {
    // a folder in which its user cannot make one: read-only to it, or, for the superuser (who
    // writes in read-only folders), /proc, where no process makes folders
    std::string unwritable = "/proc";
    if (::geteuid() != 0) {
      unwritable = dir + "/ro";
      fs::create_directories(unwritable);
      fs::permissions(unwritable, fs::perms::owner_read | fs::perms::owner_exec);
    }
    const std::string folder = unwritable + "/keller_study_" + std::to_string(::getpid());
    const auto r = test::run_keller("study " + study + " --jobs 1 -o " + folder);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("the study folder '" + folder + "' cannot be made"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(folder));
  }
  // every file, the tasks' records and the table included, limited to 1 KiB
  const auto r = test::run_keller("study " + study + " --jobs 1 -o " + dir + "/s", file_size_limit(1));
  expect_io_failure(r, dir + "/s/", "File too large");
  EXPECT_NE(r.err.find("the study stopped: its files cannot be written in " + dir + "/s/"), std::string::npos) << r.err;
}
