// Issue 30, items 5, 6, 7 and 11, through the real driver: a run never writes through a link
// planted at one of its temporary names; it publishes the file it wrote and no other; a second run
// on the same output (or study folder) is refused at its start, naming the first, which loses
// nothing; and a run killed while it publishes is published, not computed again, by the same
// command.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

const std::string bratu1d = test::source_path("runs/scenes/bratu1d_fold.toml");
const std::string bratu2d = test::source_path("runs/scenes/bratu2d_fold.toml");
const std::string quick = " --set bratu.intervals=40";
const std::string small2d = " --set bratu.intervals=8 --set continuation.save_every=2 --set continuation.max_step=0.2";

// keller started in the background in its own process group, its output in `log` and `log`.err.
pid_t start_keller(const std::string& args, const std::string& env, const std::string& log) {
  const std::string cmd = env + " exec " + KELLER_BINARY + " " + args + " >" + log + " 2>" + log + ".err";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::setpgid(pid, pid);
  return pid;
}

// Waits until the process (a child) stops itself (KELLER_SIGNAL=STOP): false if it ended instead.
bool stopped(pid_t pid) {
  int status = 0;
  return ::waitpid(pid, &status, WUNTRACED) == pid && WIFSTOPPED(status);
}

// Waits until some process of the group `group` is stopped (a study's task, a grandchild).
bool stopped_in_group(pid_t group) {
  for (int i = 0; i < 1200; ++i) {
    for (const auto& e : fs::directory_iterator("/proc")) {
      std::ifstream stat(e.path() / "stat");
      std::string line;
      if (!std::getline(stat, line)) continue;
      const auto close = line.rfind(')');
      if (close == std::string::npos) continue;
      std::istringstream rest(line.substr(close + 2));
      char state = 0;
      long ppid = 0, pgrp = 0;
      rest >> state >> ppid >> pgrp;
      if (pgrp == group && state == 'T') return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// Continues the process group (again whenever one of it stops itself) until its leader ends;
// returns the leader's exit code (-1: ended by a signal).
int resume(pid_t pid) {
  int status = 0;
  while (true) {
    ::kill(-pid, SIGCONT);
    const pid_t r = ::waitpid(pid, &status, WNOHANG | WUNTRACED);
    if (r == pid && !WIFSTOPPED(status)) break;
    if (r < 0) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Equal entry by entry, NaN equal to NaN.
bool same_table(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (long i = 0; i < a.rows(); ++i)
    for (long j = 0; j < a.cols(); ++j)
      if (!(a(i, j) == b(i, j) || (std::isnan(a(i, j)) && std::isnan(b(i, j))))) return false;
  return true;
}

}  // namespace

// Item 5: a link at the run's own temporary names (OUT.h5.part.part of a trace and of evolve, a
// CSV's .part, the copy that takes the fields, the XDMF files' NAME.pending and NAME.pending.part,
// the eigenmodes' included) is refused at the start, and the file it points to is untouched: an
// input it points to is named, any other file is refused as a link.
TEST(OutputIntegrity, NoTemporaryIsWrittenThroughALink) {
  const std::string dir = test::scratch_dir("integrity_links");
  auto r = test::run_keller("trace " + bratu1d + quick + " -o " + dir + "/b1.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_keller("trace " + bratu2d + small2d + " -o " + dir + "/b2.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  fs::copy_file(dir + "/b1.h5", dir + "/v.h5");
  const std::string b1 = test::file_contents(dir + "/b1.h5"), v = test::file_contents(dir + "/v.h5");
  fs::create_symlink(dir + "/b1.h5", dir + "/x.h5.part.part");
  fs::create_hard_link(dir + "/b1.h5", dir + "/y.h5.part.part");
  fs::create_symlink(dir + "/v.h5", dir + "/z.h5.part.part");
  fs::create_hard_link(dir + "/v.h5", dir + "/w.h5.part.part");
  fs::create_symlink(dir + "/v.h5", dir + "/e.h5.part.part");
  fs::create_hard_link(dir + "/v.h5", dir + "/t.csv.part");
  fs::create_hard_link(dir + "/v.h5", dir + "/f.h5.fields.part");
  fs::create_symlink(dir + "/v.h5", dir + "/p.xdmf.pending.part");
  fs::create_symlink(dir + "/v.h5", dir + "/q_mode0.xdmf.pending");
  fs::create_symlink(dir + "/v.h5", dir + "/b2.xdmf.pending.part");
  const std::string evolve = test::source_path("runs/scenes/brusselator1d_evolve.toml") +
                             " --set evolve.t_end=10 --set evolve.print_every=1000";
  const std::string restart = " --restart " + dir + "/b1.h5:4";
  const struct {
    std::string args, name, what;
  } cases[] = {
      {"trace " + bratu1d + quick + restart + " -o " + dir + "/x.h5", "x.h5.part.part",
       "is the same file as the --restart file"},
      {"trace " + bratu1d + quick + restart + " -o " + dir + "/y.h5", "y.h5.part.part",
       "is the same file as the --restart file"},
      {"trace " + bratu1d + quick + " -o " + dir + "/z.h5", "z.h5.part.part", "is a symbolic link"},
      {"trace " + bratu1d + quick + " -o " + dir + "/w.h5", "w.h5.part.part", "is a hard link to another file"},
      {"evolve " + evolve + " -o " + dir + "/e.h5", "e.h5.part.part", "is a symbolic link"},
      {"export " + dir + "/b1.h5 --csv " + dir + "/t.csv", "t.csv.part", "is a hard link to another file"},
      {"trace " + bratu1d + quick + " -o " + dir + "/f.h5", "f.h5.fields.part", "is a hard link to another file"},
      {"trace " + bratu2d + small2d + " -o " + dir + "/p.h5", "p.xdmf.pending.part", "is a symbolic link"},
      {"trace " + bratu2d + small2d + " --set stability.enabled=true -o " + dir + "/q.h5", "q_mode0.xdmf.pending",
       "is a symbolic link"},
      {"export " + dir + "/b2.h5 --xdmf", "b2.xdmf.pending.part", "is a symbolic link"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.args);
    r = test::run_keller(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(c.name + "' " + c.what), std::string::npos) << r.err;
    EXPECT_TRUE(test::file_contents(dir + "/b1.h5") == b1) << "b1.h5 changed";
    EXPECT_TRUE(test::file_contents(dir + "/v.h5") == v) << "v.h5 changed";
  }
  for (const char* name : {"x.h5", "y.h5", "z.h5", "w.h5", "e.h5", "t.csv", "f.h5", "p.h5", "q.h5", "b2-fields.h5"})
    EXPECT_FALSE(fs::exists(dir + "/" + name)) << name;
}

// Item 6: the file at OUT.h5.part replaced while the run traced is not published: exit 3, the
// earlier OUT.h5 and the stranger's file as they were, and the run's own branch saved beside them.
TEST(OutputIntegrity, OnlyTheFileTheRunWroteIsPublished) {
  const std::string dir = test::scratch_dir("integrity_swap");
  auto r = test::run_keller("trace " + bratu1d + quick + " -o " + dir + "/b1.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_keller("trace " + bratu2d + small2d + " -o " + dir + "/reference.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const long rows = read_branch_table(dir + "/reference.h5").rows.rows();
  const std::string out = dir + "/c.h5", work = out + ".part";
  fs::copy_file(dir + "/b1.h5", out);
  const std::string earlier = test::file_contents(out);
  const pid_t pid = start_keller("trace " + bratu2d + small2d + " -o " + out,
                                 "KELLER_SIGNAL_AT=traced KELLER_SIGNAL=STOP", dir + "/run.log");
  ASSERT_TRUE(stopped(pid));
  fs::remove(work);
  fs::copy_file(dir + "/b1.h5", work);
  EXPECT_EQ(resume(pid), 3) << test::file_contents(dir + "/run.log");
  const std::string err = test::file_contents(dir + "/run.log.err");
  EXPECT_NE(err.find("'" + work + "' is not the file this run wrote"), std::string::npos) << err;
  EXPECT_TRUE(test::file_contents(out) == earlier) << "changed";
  EXPECT_TRUE(test::file_contents(work) == test::file_contents(dir + "/b1.h5")) << "changed";
  const std::string saved = work + "." + std::to_string(pid);
  EXPECT_NE(err.find("saved as '" + saved + "'"), std::string::npos) << err;
  ASSERT_TRUE(fs::exists(saved));
  const BranchTable t = read_branch_table(saved);
  EXPECT_EQ(t.rows.rows(), rows);
  EXPECT_NE(t.status, "running");
  EXPECT_FALSE(fs::exists(dir + "/c.xdmf"));
}

// Item 7: a second trace on an output that a run is writing is refused at its start, naming the
// first; the first then finishes its whole branch under its name, and leaves no lock behind.
TEST(OutputIntegrity, ASecondWriterOfAnOutputIsRefusedNamingTheFirst) {
  const std::string dir = test::scratch_dir("integrity_two");
  auto r = test::run_keller("trace " + bratu2d + small2d + " -o " + dir + "/reference.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable reference = read_branch_table(dir + "/reference.h5");
  const std::string out = dir + "/c.h5";
  const std::string command = "trace " + bratu2d + small2d + " -o " + out;
  const pid_t pid = start_keller(command, "KELLER_SIGNAL_AT=point:3 KELLER_SIGNAL=STOP", dir + "/first.log");
  ASSERT_TRUE(stopped(pid));
  const std::string part = test::file_contents(out + ".part");
  for (const std::string& second :
       {command, "solve " + bratu2d + " -o " + out,
        "evolve " + test::source_path("runs/scenes/brusselator1d_evolve.toml") + " -o " + out}) {
    SCOPED_TRACE(second);
    r = test::run_keller(second);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(
        r.err.find("is in use by another keller process (pid " + std::to_string(pid) + ", lock '" + out + ".lock')"),
        std::string::npos)
        << r.err;
    EXPECT_TRUE(test::file_contents(out + ".part") == part) << "changed";
  }
  EXPECT_EQ(resume(pid), 0) << test::file_contents(dir + "/first.log.err");
  const BranchTable t = read_branch_table(out);
  EXPECT_EQ(t.rows.rows(), reference.rows.rows());
  EXPECT_EQ(t.status, reference.status);
  for (const std::string& left : {out + ".part", out + ".lock"}) EXPECT_FALSE(fs::exists(left)) << left;
}

// Item 7 for studies: a second `keller study` on a folder that a study is running in is refused
// at its start, naming the first, whose tasks all end done.
TEST(OutputIntegrity, ASecondStudyOnAFolderIsRefusedNamingTheFirst) {
  const std::string dir = test::scratch_dir("integrity_study");
  const std::string study = dir + "/s.toml";
  std::ofstream(study) << "[study]\nscene = \"" << bratu1d
                       << "\"\n\n[set]\n\"output.xdmf\" = false\n\n[grid]\n\"bratu.intervals\" = [16, 24]\n"
                          "\"continuation.max_step\" = [0.3, 0.5]\n";
  const std::string command = "study " + study + " --jobs 1 -o " + dir + "/s";
  const pid_t pid = start_keller(command, "KELLER_SIGNAL_AT=point:3 KELLER_SIGNAL=STOP", dir + "/first.log");
  ASSERT_TRUE(stopped_in_group(pid));  // its first task, at its third point
  const auto r = test::run_keller(command);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("is in use by another keller process (pid " + std::to_string(pid) + ", lock '" + dir +
                       "/s/study.lock')"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(resume(pid), 0) << test::file_contents(dir + "/first.log") << test::file_contents(dir + "/first.log.err");
  EXPECT_NE(test::file_contents(dir + "/first.log").find("(4 done, 0 failed, 0 not run)"), std::string::npos)
      << test::file_contents(dir + "/first.log");
  EXPECT_FALSE(fs::exists(dir + "/s/study.lock"));
}

// Item 7 for a study's task: a duplicate of a running task (`keller study run --task K` again, as a
// batch system may requeue it) is refused before it touches anything, even where the study file
// has changed meanwhile and the running task's unfinished output looks like another task's: it is
// not set aside; the duplicate is recorded as interrupted, saying that another process runs the
// task (not as failed), and the running task completes.
TEST(OutputIntegrity, ADuplicateOfARunningTaskLeavesItAlone) {
  const std::string dir = test::scratch_dir("integrity_task");
  const std::string study = dir + "/s.toml";
  const auto write_study = [&](const std::string& max_step) {
    std::ofstream(study) << "[study]\nscene = \"" << bratu1d << "\"\n\n[set]\n\"output.xdmf\" = false\n"
                         << "\"continuation.max_step\" = " << max_step << "\n\n[grid]\n\"bratu.intervals\" = [40]\n";
  };
  write_study("0.3");
  const std::string command = "study run " + study + " --task 0 -o " + dir + "/s";
  const pid_t pid = start_keller(command, "KELLER_SIGNAL_AT=point:3 KELLER_SIGNAL=STOP", dir + "/first.log");
  ASSERT_TRUE(stopped(pid));  // at its third point
  std::string part;
  for (const auto& e : fs::directory_iterator(dir + "/s/tasks"))
    if (e.path().string().size() > 8 && e.path().string().substr(e.path().string().size() - 8) == ".h5.part")
      part = e.path().string();
  ASSERT_FALSE(part.empty());
  const std::string record = part.substr(0, part.size() - 8) + ".toml";
  write_study("0.25");  // the task as the duplicate sees it: its running output is another's
  const auto r = test::run_keller(command);
  EXPECT_EQ(r.exit_code, 130) << r.out << r.err;
  EXPECT_NE(r.err.find("is in use by another keller process (pid " + std::to_string(pid) + ","), std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::exists(part));
  EXPECT_FALSE(fs::exists(dir + "/s/set_aside"));
  EXPECT_NE(test::file_contents(record).find("status = \"interrupted\""), std::string::npos)
      << test::file_contents(record);
  EXPECT_EQ(resume(pid), 0) << test::file_contents(dir + "/first.log") << test::file_contents(dir + "/first.log.err");
  EXPECT_FALSE(fs::exists(part));
  EXPECT_NE(test::file_contents(record).find("status = \"done\""), std::string::npos) << test::file_contents(record);
}

// A run killed as it ends, after its last point and before its end is marked for publication (as
// an IoError there would leave it: disk full at the very end), is finished by the same command
// from OUT.h5.part, not computed again: the published table is the killed run's to the bit, for a
// branch and a time series.
TEST(OutputIntegrity, ARunKilledAsItEndsIsFinishedNotComputedAgain) {
  const std::string dir = test::scratch_dir("integrity_ended");
  const std::string evolve = test::source_path("runs/scenes/brusselator1d_evolve.toml") +
                             " --set evolve.t_end=10 --set evolve.print_every=1000";
  const struct {
    std::string command;
    bool series;
  } cases[] = {
      {"trace " + bratu2d + small2d + " -o " + dir + "/k.h5", false},
      {"evolve " + evolve + " -o " + dir + "/k.h5", true},
  };
  const std::string out = dir + "/k.h5", work = out + ".part";
  for (const auto& c : cases) {
    SCOPED_TRACE(c.command);
    for (const std::string& f : {out, work, dir + "/k.xdmf"}) fs::remove(f);
    auto r = test::run_keller(c.command, "KELLER_SIGNAL_AT=ended KELLER_SIGNAL=KILL");
    ASSERT_EQ(r.exit_code, -1) << r.out << r.err;
    ASSERT_TRUE(fs::exists(work));
    const Eigen::MatrixXd killed = c.series ? read_time_table(work).rows : read_branch_table(work).rows;
    r = test::run_keller(c.command);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(r.out.find("this run replaces it"), std::string::npos) << r.out;
    const Eigen::MatrixXd published = c.series ? read_time_table(out).rows : read_branch_table(out).rows;
    EXPECT_TRUE(same_table(published, killed)) << "not the killed run's table";
    EXPECT_FALSE(fs::exists(work));
  }
}

// Item 11: a run killed after its last point, while its fields are written or once it has taken
// its name, is finished by the same command from its complete OUT.h5.part, not computed again:
// the published table is the killed run's to the bit (its `seconds` column included), for a
// branch, a fold curve and a time series.
TEST(OutputIntegrity, ARunKilledWhilePublishingIsPublishedNotComputedAgain) {
  const std::string dir = test::scratch_dir("integrity_publish");
  auto r = test::run_keller("trace " + bratu2d + small2d + " -o " + dir + "/b.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable branch = read_branch_table(dir + "/b.h5");
  long fold = -1;
  for (long i = 0; i < branch.rows.rows(); ++i)
    if (static_cast<int>(branch.rows(i, branch.column("kind"))) == static_cast<int>(PointKind::Fold)) fold = i;
  ASSERT_GE(fold, 0);
  const std::string shifted =
      test::source_path("runs/scenes/bratu1d_shifted_fold_curve.toml") + " --set bratu.intervals=32";
  r = test::run_keller("trace " + shifted + " -o " + dir + "/s.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable s = read_branch_table(dir + "/s.h5");
  long shifted_fold = -1;
  for (long i = 0; i < s.rows.rows(); ++i)
    if (static_cast<int>(s.rows(i, s.column("kind"))) == static_cast<int>(PointKind::Fold)) shifted_fold = i;
  ASSERT_GE(shifted_fold, 0);
  const std::string evolve = test::source_path("runs/scenes/brusselator1d_evolve.toml") +
                             " --set evolve.t_end=10 --set evolve.print_every=1000";
  const struct {
    std::string command, at, xdmf;
    bool series;
  } cases[] = {
      {"trace " + bratu2d + small2d + " -o " + dir + "/k.h5", "traced", "k.xdmf", false},
      {"trace " + bratu2d + small2d + " -o " + dir + "/k.h5", "fields:2", "k.xdmf", false},
      {"trace " + bratu2d + small2d + " -o " + dir + "/k.h5", "fields-written", "k.xdmf", false},
      {"trace " + bratu2d + small2d + " -o " + dir + "/k.h5", "published", "k.xdmf", false},
      {"trace " + shifted + " -o " + dir + "/k.h5 --from " + dir + "/s.h5:" + std::to_string(shifted_fold) +
           " --curve fold --free mu",
       "traced", "", false},
      {"evolve " + evolve + " -o " + dir + "/k.h5", "evolved", "", true},
  };
  const std::string out = dir + "/k.h5", work = out + ".part";
  for (const auto& c : cases) {
    SCOPED_TRACE(c.command + " killed at " + c.at);
    for (const std::string& f : {out, work, out + ".fields.part", dir + "/k.xdmf"}) fs::remove(f);
    r = test::run_keller(c.command, "KELLER_SIGNAL_AT=" + c.at + " KELLER_SIGNAL=KILL");
    ASSERT_EQ(r.exit_code, -1) << r.out << r.err;
    ASSERT_TRUE(fs::exists(work));
    const Eigen::MatrixXd killed = c.series ? read_time_table(work).rows : read_branch_table(work).rows;
    r = test::run_keller(c.command);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("ended before it was published; publishing it"), std::string::npos) << r.out;
    const Eigen::MatrixXd published = c.series ? read_time_table(out).rows : read_branch_table(out).rows;
    EXPECT_TRUE(same_table(published, killed)) << "not the killed run's table";
    EXPECT_FALSE(fs::exists(work));
    EXPECT_FALSE(fs::exists(out + ".fields.part"));
    if (!c.xdmf.empty()) {
      EXPECT_TRUE(fs::exists(dir + "/" + c.xdmf));
    }
  }
}
