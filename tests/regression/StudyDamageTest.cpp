// keller study after damage and interruptions: a study killed with SIGKILL and run again runs
// only what was unfinished and ends with the same table, and a changed override reruns only the
// tasks it changes; a task whose process dies is run once more, then recorded as failed. Issue 30:
// outputs damaged or replaced between runs are set aside and their tasks run again; a continued
// task's cost adds up its runs; a signal to the study alone stops its running tasks.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <thread>

#include "continuation/output/BranchFile.hpp"
#include "support/StudySupport.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
using test::bratu_study;
using test::count;
using test::table_without_time;
namespace fs = std::filesystem;

TEST(Study, AKilledStudyRunsOnlyWhatWasUnfinished) {
  const std::string dir = test::scratch_dir("study_kill");
  const std::string study = bratu_study(dir);
  auto r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/reference");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string reference = table_without_time(dir + "/reference/bratu.csv");
  // the study killed with SIGKILL once four tasks have their records
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (!freopen("/dev/null", "w", stdout)) _exit(3);
    execl(KELLER_BINARY, "keller", "study", study.c_str(), "--jobs", "1", "-o", (dir + "/s").c_str(),
          static_cast<char*>(nullptr));
    _exit(127);
  }
  auto records = [&]() {
    int n = 0;
    if (fs::exists(dir + "/s/tasks"))
      for (const auto& e : fs::directory_iterator(dir + "/s/tasks")) n += e.path().extension() == ".toml";
    return n;
  };
  const auto t0 = std::chrono::steady_clock::now();
  while (records() < 4 && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the study ended before it was killed";
  const int finished = records();
  ASSERT_GE(finished, 4);
  ASSERT_LT(finished, 12);
  std::map<std::string, fs::file_time_type> kept;
  for (const auto& e : fs::directory_iterator(dir + "/s/tasks"))
    if (e.path().extension() == ".toml") kept[e.path().string()] = fs::last_write_time(e.path());
  r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/s");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(fmt::format("{} done before, {} to run", finished, 12 - finished)), std::string::npos) << r.out;
  EXPECT_EQ(count(r.out, "] task "), 12 - finished);
  for (const auto& [path, time] : kept) EXPECT_EQ(fs::last_write_time(path), time) << path << " ran again";
  EXPECT_EQ(table_without_time(dir + "/s/bratu.csv"), reference);
  // a changed override reruns the four tasks it changes, and only those
  bratu_study(dir, "2.0, 3.0, 3.5");
  r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/s");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("8 done before, 4 to run"), std::string::npos) << r.out;
  EXPECT_EQ(count(r.out, "continuation.stop_above=3.5"), 4) << r.out;
}

// A task whose process dies (here every task kills itself at its third point) is reported, run
// once more, then recorded as failed with the signal; the study goes on to the end.
TEST(Study, ATaskWhoseProcessDiesIsRunAgainThenRecordedAsFailed) {
  const std::string dir = test::scratch_dir("study_died");
  const std::string study = dir + "/died.toml";
  std::ofstream(study) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml") << "\"\n"
                       << "[set]\n\"output.xdmf\" = false\n[grid]\n\"bratu.intervals\" = [16, 24]\n";
  std::vector<std::pair<std::string, std::string>> executors = {{"--jobs 2", "local"}};
  if (!std::string(KELLER_MPIRUN).empty()) executors.push_back({"mpi", "mpi"});
  for (const auto& [how, name] : executors) {
    SCOPED_TRACE(name);
    const std::string out = dir + "/" + name;
    const std::string env = "KELLER_SIGNAL_AT=point:3 KELLER_SIGNAL=KILL";
    test::CommandResult r;
    if (how == "mpi") {
      const std::string cmd = env + " " + std::string(KELLER_MPIRUN) + " --allow-run-as-root --oversubscribe -n 3 " +
                              KELLER_BINARY + " study " + study + " -o " + out + " > " + dir + "/mpi.log 2>&1";
      r.exit_code = WEXITSTATUS(std::system(cmd.c_str()));
      r.out = test::file_contents(dir + "/mpi.log");
    } else {
      r = test::run_keller("study " + study + " " + how + " -o " + out, env);
    }
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_EQ(count(r.out, "running it again"), 2) << r.out;
    EXPECT_NE(r.out.find("collected 2 tasks (0 done, 2 failed, 0 not run)"), std::string::npos) << r.out;
    for (const auto& row : test::read_table(out + "/died.csv")) {
      EXPECT_EQ(row.at("status"), "failed");
      EXPECT_EQ(row.at("reason"), "its process died of signal 9 (Killed)");
      EXPECT_EQ(row.at("attempts"), "2");
    }
  }
}

// Issue 30, item 9: outputs damaged between runs of a study (truncated, emptied, replaced by a
// folder) or replaced by another task's output are never collected as the task's; the next run
// sets each aside under FOLDER/set_aside/ (saying so), runs those tasks again and ends with the
// undisturbed table. The set-aside files are moved, not lost.
TEST(Study, ADamagedOrForeignOutputIsSetAsideAndItsTaskRunAgain) {
  const std::string dir = test::scratch_dir("study_damaged");
  const std::string study = dir + "/damage.toml";
  std::ofstream(study) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml") << "\"\n"
                       << "[set]\n\"output.xdmf\" = false\n\"continuation.renewal_cost\" = 25.0\n"
                       << "[grid]\n\"bratu.intervals\" = [16, 24, 32, 48, 128]\n[collect]\nevents = [\"fold\"]\n";
  auto r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/d");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string reference = table_without_time(dir + "/d/damage.csv");
  std::map<std::string, std::string> output;  // by intervals
  for (const auto& row : test::read_table(dir + "/d/damage.csv"))
    output[row.at("bratu.intervals")] = dir + "/d/tasks/" + row.at("name") + ".h5";
  ASSERT_EQ(output.size(), 5u);
  fs::resize_file(output["16"], fs::file_size(output["16"]) / 2);  // truncated
  fs::resize_file(output["24"], 0);                                // emptied
  fs::remove(output["32"]);                                        // a folder in its place, with a file in it
  fs::create_directory(output["32"]);
  std::ofstream(output["32"] + "/keep.txt") << "mine\n";
  fs::copy_file(output["128"], output["48"], fs::copy_options::overwrite_existing);  // another task's
  const std::string foreign = test::file_contents(output["48"]);

  // collected as they are: none of them is done, and the 128-interval fold is not task 48's
  r = test::run_keller("study collect " + study + " -o " + dir + "/d");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const auto& row : test::read_table(dir + "/d/damage.csv")) {
    const bool damaged = row.at("bratu.intervals") != "128";
    EXPECT_EQ(row.at("status"), damaged ? "damaged" : "done") << row.at("name");
    EXPECT_EQ(row.at("event:fold").empty(), damaged) << row.at("name");
  }
  const auto row48 = test::read_table(dir + "/d/damage.csv")[3];
  EXPECT_NE(row48.at("reason").find("holds another run"), std::string::npos) << row48.at("reason");
  EXPECT_NE(row48.at("reason").find("bratu.intervals = 128 in the file, 48 in this scene"), std::string::npos)
      << row48.at("reason");
  const auto list = test::run_keller("study list " + study + " -o " + dir + "/d");
  EXPECT_EQ(count(list.out, " damaged "), 4) << list.out;

  // the next run sets the four aside and runs them again
  r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/d");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("1 done before, 4 to run"), std::string::npos) << r.out;
  EXPECT_EQ(count(r.out, "set aside as "), 4) << r.out;
  EXPECT_EQ(table_without_time(dir + "/d/damage.csv"), reference);
  const auto aside = [&](const std::string& intervals) {
    return dir + "/d/set_aside/" + fs::path(output[intervals]).stem().string() + "-1.h5";
  };
  EXPECT_EQ(fs::file_size(aside("24")), 0u);
  EXPECT_EQ(test::file_contents(aside("32") + "/keep.txt"), "mine\n");
  EXPECT_EQ(test::file_contents(aside("48")), foreign);
  // and a study run again finds everything done
  r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/d");
  EXPECT_NE(r.out.find("5 done before, 0 to run"), std::string::npos) << r.out;
}

namespace {

// One task, a 247-row Bratu branch of about 2 s: small steps on a fine grid, every solution stored.
std::string long_task_study(const std::string& dir) {
  const std::string path = dir + "/long.toml";
  std::ofstream(path) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml") << "\"\n"
                      << "[set]\n\"output.xdmf\" = false\n\"continuation.renewal_cost\" = 25.0\n"
                      << "\"continuation.save_every\" = 1\n\"continuation.initial_step\" = 0.02\n"
                      << "\"continuation.max_step\" = 0.02\n[grid]\n\"bratu.intervals\" = [2000]\n"
                      << "[collect]\nend = [\"u_mid\"]\n";
  return path;
}

// The sums over the summary lines a task's log holds, one per run ("N points, R rejected steps,
// F factorisations ...", "time T s: ..."): runs, points, factorisations, seconds.
std::array<double, 4> logged_costs(const std::string& log) {
  std::array<double, 4> sum{};
  const std::string text = test::file_contents(log);
  const std::regex summary(R"((\d+) points, (\d+) rejected steps, (\d+) factorisations)"),
      time(R"(\ntime ([0-9.]+) s:)");
  for (std::sregex_iterator it(text.begin(), text.end(), summary), end; it != end; ++it) {
    sum[0] += 1;
    sum[1] += std::stod((*it)[1]);
    sum[2] += std::stod((*it)[3]);
  }
  for (std::sregex_iterator it(text.begin(), text.end(), time), end; it != end; ++it) sum[3] += std::stod((*it)[1]);
  return sum;
}

}  // namespace

// Issue 30, item 10: the cost columns of a task interrupted and continued by the next run of the
// study add up both runs (the first run's cost is kept in the task's record, status interrupted,
// which the continuing run adds its own to): its points are the rows of the branch, once each (the
// continued run's first row is the first run's last), its factorisations and seconds those of both
// runs' summaries.
TEST(Study, TheCostOfAContinuedTaskAddsUpItsRuns) {
  const std::string dir = test::scratch_dir("study_cost");
  const std::string study = long_task_study(dir);
  auto r = test::run_keller("study " + study + " -o " + dir + "/ref");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto ref = test::read_table(dir + "/ref/long.csv").at(0);
  ASSERT_EQ(ref.at("points"), "247");
  // the task stops after its 40th point: the study is interrupted
  r = test::run_keller("study " + study + " -o " + dir + "/s", "KELLER_SIGNAL_AT=point:40 KELLER_SIGNAL=TERM");
  EXPECT_EQ(r.exit_code, 130) << r.out << r.err;
  EXPECT_EQ(test::read_table(dir + "/s/long.csv").at(0).at("status"), "interrupted");
  r = test::run_keller("study " + study + " -o " + dir + "/s");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto row = test::read_table(dir + "/s/long.csv").at(0);
  const std::string log = dir + "/s/tasks/" + row.at("name") + ".log";
  const auto [runs, points, factorisations, seconds] = logged_costs(log);
  ASSERT_EQ(runs, 2) << test::file_contents(log);
  EXPECT_EQ(row.at("runs"), "2");
  EXPECT_EQ(points, 40 + 208);  // (the second run's first point is the first run's 40th)
  EXPECT_EQ(row.at("points"), "247");
  EXPECT_EQ(read_branch_table(dir + "/s/tasks/" + row.at("name") + ".h5").rows.rows(), 247);
  EXPECT_EQ(std::stod(row.at("factorisations")), factorisations);
  // the log prints each run's seconds to 2 decimals, each within 0.005 of the recorded value: their
  // sum within 0.01 of the record's sum, and 0.001 more for the binary values of those decimals
  EXPECT_NEAR(std::stod(row.at("seconds")), seconds, 0.011);
  EXPECT_NEAR(std::stod(row.at("end:u_mid")), std::stod(ref.at("end:u_mid")), 1e-9);
  EXPECT_GT(std::stod(row.at("process_seconds")), std::stod(row.at("seconds")));
  // the same for the task run alone, as a batch scheduler runs it (its summaries on the terminal)
  r = test::run_keller("study run " + study + " --task 0 -o " + dir + "/b",
                       "KELLER_SIGNAL_AT=point:40 KELLER_SIGNAL=TERM");
  EXPECT_EQ(r.exit_code, 130) << r.out << r.err;
  std::string printed = r.out;
  r = test::run_keller("study run " + study + " --task 0 -o " + dir + "/b");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  printed += r.out;
  std::ofstream(dir + "/b.log") << printed;
  r = test::run_keller("study collect " + study + " -o " + dir + "/b");
  const auto batch = test::read_table(dir + "/b/long.csv").at(0);
  EXPECT_EQ(batch.at("runs"), "2");
  EXPECT_EQ(batch.at("points"), "247");
  EXPECT_EQ(std::stod(batch.at("factorisations")), logged_costs(dir + "/b.log")[2]);
}

// Issue 30, item 11 in a study: a task killed while its branch is published (after its last point)
// is published by its next run, not computed again, and the table keeps the task's cost: its points
// the rows of the branch, its other costs those its earlier runs recorded (a run killed leaves no
// record of its own). Here the task is interrupted at its 40th point, then its continuation is
// killed as its branch is published, and the study runs the task again at once.
TEST(Study, ATaskKilledWhilePublishingKeepsItsCost) {
  const std::string dir = test::scratch_dir("study_publish");
  const std::string study = long_task_study(dir);
  auto r = test::run_keller("study " + study + " -o " + dir + "/s", "KELLER_SIGNAL_AT=point:40 KELLER_SIGNAL=TERM");
  ASSERT_EQ(r.exit_code, 130) << r.out << r.err;
  const auto first = test::read_table(dir + "/s/long.csv").at(0);
  ASSERT_EQ(first.at("status"), "interrupted");
  ASSERT_GT(std::stod(first.at("factorisations")), 0);
  r = test::run_keller("study " + study + " -o " + dir + "/s", "KELLER_SIGNAL_AT=traced KELLER_SIGNAL=KILL");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(count(r.out, "running it again"), 1) << r.out;
  const auto row = test::read_table(dir + "/s/long.csv").at(0);
  const std::string log = test::file_contents(dir + "/s/tasks/" + row.at("name") + ".log");
  EXPECT_EQ(count(log, "ended before it was published; publishing it"), 1) << log;
  EXPECT_EQ(row.at("status"), "done");
  EXPECT_EQ(row.at("points"), "247");
  EXPECT_EQ(read_branch_table(dir + "/s/tasks/" + row.at("name") + ".h5").rows.rows(), 247);
  EXPECT_EQ(row.at("runs"), "2");
  for (const char* cost : {"unknowns", "factorisations", "rejected", "solves", "seconds", "factor_seconds",
                           "solve_seconds", "lu_backend", "nnz_lu", "lu_peak_mb"})
    EXPECT_EQ(row.at(cost), first.at(cost)) << cost;
}

// Issue 30, item 10: SIGTERM or SIGINT to the study's process alone reaches its running task,
// which stops after its current point (not at the end of its branch); the study exits 130 and
// its next run continues the task to the undisturbed branch.
TEST(Study, ASignalToTheStudyAloneStopsItsRunningTask) {
  const std::string dir = test::scratch_dir("study_signal");
  const std::string study = long_task_study(dir);
  auto r = test::run_keller("study " + study + " -o " + dir + "/ref");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto ref = test::read_table(dir + "/ref/long.csv").at(0);
  const std::string part = dir + "/s/tasks/" + ref.at("name") + ".h5.part";
  for (const int sig : {SIGTERM, SIGINT}) {
    SCOPED_TRACE(strsignal(sig));
    fs::remove_all(dir + "/s");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      if (!freopen("/dev/null", "w", stdout)) _exit(3);
      execl(KELLER_BINARY, "keller", "study", study.c_str(), "-o", (dir + "/s").c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    const auto t0 = std::chrono::steady_clock::now();
    while (!fs::exists(part) && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30))
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // some points into the branch
    ASSERT_EQ(kill(pid, sig), 0);
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    const auto row = test::read_table(dir + "/s/long.csv").at(0);
    EXPECT_EQ(row.at("status"), "interrupted");
    ASSERT_TRUE(fs::exists(part));
    const long kept = read_branch_table(part).rows.rows();  // stopped short of its 247 rows
    EXPECT_GT(kept, 1);
    EXPECT_LT(kept, 247);
    r = test::run_keller("study " + study + " -o " + dir + "/s");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const auto done = test::read_table(dir + "/s/long.csv").at(0);
    EXPECT_EQ(done.at("status"), "done");
    EXPECT_EQ(done.at("points"), "247");
    EXPECT_NEAR(std::stod(done.at("end:u_mid")), std::stod(ref.at("end:u_mid")), 1e-9);
  }
}
