// keller study end to end: the same collected table under every executor (one worker, two, the
// ranks of mpirun); a study killed with SIGKILL and run again runs only what was unfinished and
// ends with the same table, and a changed override reruns only the tasks it changes; a task
// that fails is recorded with its reason while the others complete; a bad study file stops
// before any task; and a branch started from a stored point of a branch in another parameter
// is the branch started from a fresh solve there. Issue 30: outputs damaged or replaced between
// runs are set aside and their tasks run again; a continued task's cost adds up its runs; a
// signal to the study alone stops its running tasks; a task's process checks its task alone;
// tasks that resolve to the same run are refused.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "continuation/BranchFile.hpp"
#include "core/H5File.hpp"
#include "runs/OutputFile.hpp"
#include "runs/study/StudyRunner.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

// 12 short Bratu branches: 4 grids x 3 ends, the fold and u(1/2) at the stops collected. The
// renewal cost is pinned: by default the chord's renewals follow the run's measured times, so two
// runs under different loads may differ in their factorisations and in the last digits (below the
// corrector's tolerance); pinned, every run of a task is the same to the bit, which is what these
// tests compare across executors and restarts.
std::string bratu_study(const std::string& dir, const std::string& ends = "2.0, 3.0, 4.0") {
  const std::string path = dir + "/bratu.toml";
  std::ofstream(path) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml")
                      << "\"\n\n[set]\n\"output.xdmf\" = false\n\"continuation.renewal_cost\" = "
                         "25.0\n\n[grid]\n\"bratu.intervals\" = [16, 24, 32, 48]\n"
                      << "\"continuation.stop_above\" = [" << ends << "]\n\n[collect]\nevents = [\"fold\", \"u_mid\"]\n"
                      << "stops = [\"u_mid\"]\nend = [\"u_mid\"]\n";
  return path;
}

// The collected CSV without the columns that measure time and memory (the rest is deterministic).
std::string table_without_time(const std::string& csv) {
  const std::set<std::string> timed_columns = {"seconds", "process_seconds", "peak_mb", "factor_seconds",
                                               "solve_seconds"};
  std::ifstream in(csv);
  std::string line, out;
  std::set<size_t> timed;
  bool header = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (header)
      for (size_t i = 0; i < cells.size(); ++i)
        if (timed_columns.count(cells[i])) timed.insert(i);
    header = false;
    for (size_t i = 0; i < cells.size(); ++i)
      if (!timed.count(i)) out += cells[i] + ",";
    out += "\n";
  }
  return out;
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

}  // namespace

TEST(Study, TheSameTableUnderEveryExecutor) {
  const std::string dir = test::scratch_dir("study_executors");
  const std::string study = bratu_study(dir);
  auto r = test::run_keller("study " + study + " --jobs 1 -o " + dir + "/one");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(count(r.out, "] task "), 12) << r.out;  // a line per finished task
  EXPECT_NE(r.out.find("collected 12 tasks (12 done, 0 failed, 0 not run)"), std::string::npos) << r.out;
  const std::string one = table_without_time(dir + "/one/bratu.csv");
  EXPECT_EQ(count(one, "\n"), 13);
  // what was collected: every branch passes its fold, which converges to the continuum's
  // 3.513830719125 at second order in the grid (the error is 1.83 h^2 for h = 1/16 ... 1/48),
  // and ends where u(1/2) crosses its threshold, which is where the event u_mid is located
  const auto rows = test::read_table(dir + "/one/bratu.csv");
  ASSERT_EQ(rows.size(), 12u);
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("status"), "done");
    const double h = 1.0 / std::stod(row.at("bratu.intervals"));
    EXPECT_NEAR(std::stod(row.at("event:fold")), 3.513830719125, 2 * h * h) << row.at("name");
    EXPECT_EQ(row.at("event:u_mid"), row.at("end_parameter")) << row.at("name");
    EXPECT_NEAR(std::stod(row.at("end:u_mid")), std::stod(row.at("continuation.stop_above")), 1e-8);
    // the cost of the linear algebra: J (tridiagonal, n - 1 unknowns) factorised on its own by
    // the block elimination, without fill: nnz(L + U) = nnz(J) = 3 (n - 1) - 2; a solve per
    // corrector iteration at least
    const double m = std::stod(row.at("bratu.intervals")) - 1;
    EXPECT_EQ(std::stod(row.at("nnz_lu")), 3 * m - 2) << row.at("name");
    EXPECT_GE(std::stod(row.at("solves")), std::stod(row.at("points"))) << row.at("name");
    EXPECT_GT(std::stod(row.at("lu_peak_mb")), 0.0) << row.at("name");
  }
  r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/two");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(table_without_time(dir + "/two/bratu.csv"), one);
  if (std::string(KELLER_MPIRUN).empty()) GTEST_SKIP() << "no mpirun: the MPI executor is not tested";
  const std::string mpi = std::string(KELLER_MPIRUN) + " --allow-run-as-root --oversubscribe -n 3 " + KELLER_BINARY +
                          " study " + study + " -o " + dir + "/mpi > " + dir + "/mpi.log 2>&1";
  ASSERT_EQ(std::system(mpi.c_str()), 0) << test::file_contents(dir + "/mpi.log");
  EXPECT_EQ(table_without_time(dir + "/mpi/bratu.csv"), one);
  EXPECT_EQ(count(test::file_contents(dir + "/mpi.log"), "] task "), 12);
}

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

// A study run by a keller that did not have a key yet (its records and hashes without it) is done
// for a keller that has it at its default: the tasks are not run again. (The key here,
// linear_solver.pivot_tolerance, stands in for one added since; it is at its default in the study.)
TEST(Study, TasksDoneBeforeAKeyExistedAreDoneAtItsDefault) {
  const std::string dir = test::scratch_dir("study_new_key");
  const std::string study = bratu_study(dir);
  auto r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/s");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string line_of = "linear_solver.pivot_tolerance = ";
  int rewritten = 0;
  for (const auto& e : fs::directory_iterator(dir + "/s/tasks")) {
    if (e.path().extension() != ".h5") continue;
    std::string run;
    {
      H5File f(e.path().string(), H5File::Mode::ReadWrite);
      run = f.read_string("/problem/run");
      const auto at = run.find(line_of);
      ASSERT_NE(at, std::string::npos) << run;
      run.erase(at, run.find('\n', at) + 1 - at);
      f.remove("/problem/run");
      f.write_string("/problem/run", run);
    }
    // the task's record as that keller wrote it: the hash of its record without the key
    fs::path toml = e.path();
    toml.replace_extension(".toml");
    std::string text = test::file_contents(toml.string());
    const auto at = text.find("hash = \"");
    ASSERT_NE(at, std::string::npos) << text;
    text.replace(at + 8, 16, text_hash(run));
    std::ofstream(toml) << text;
    ++rewritten;
  }
  ASSERT_EQ(rewritten, 12);
  r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/s");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("12 done before, 0 to run"), std::string::npos) << r.out;
  EXPECT_EQ(count(r.out, "] task "), 0) << r.out;
}

TEST(Study, AFailedTaskIsRecordedAndTheOthersComplete) {
  const std::string dir = test::scratch_dir("study_fail");
  const std::string study = dir + "/mixed.toml";
  std::ofstream(study) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml") << "\"\n"
                       << "[set]\n\"bratu.intervals\" = 16\n\"output.xdmf\" = false\n"
                       // no steady state at lambda = 20 (beyond the fold): Newton fails at the first state
                       << "[[cases]]\n\"bratu.lambda\" = 20.0\n\"newton.max_iterations\" = 5\n"
                       << "[[cases]]\n\"bratu.lambda\" = 0.0\n"
                       // valid for the schema, refused when the problem is built
                       << "[[cases]]\nscene = \"" << test::source_path("runs/scenes/bratu2d_fold.toml")
                       << "\"\n\"bratu.intervals\" = 5000\n"
                       << "[[cases]]\n\"bratu.lambda\" = 0.5\n"
                       << "[collect]\nevents = [\"fold\"]\n";
  const auto r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/m");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;  // some task failed
  EXPECT_NE(r.out.find("collected 4 tasks (2 done, 2 failed, 0 not run)"), std::string::npos) << r.out;
  const std::string csv = test::file_contents(dir + "/m/mixed.csv");
  EXPECT_NE(csv.find("failed,the first steady state failed"), std::string::npos) << csv;
  EXPECT_NE(csv.find("bratu2d takes at most 4000 elements per side"), std::string::npos) << csv;
  EXPECT_EQ(count(csv, ",done,"), 2) << csv;
  // the list says the same, and a rerun runs the failed tasks again
  const auto list = test::run_keller("study list " + study + " -o " + dir + "/m");
  EXPECT_EQ(count(list.out, " failed "), 2) << list.out;
  const auto again = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/m");
  EXPECT_NE(again.out.find("2 done before, 2 to run"), std::string::npos) << again.out;
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

TEST(Study, ABadStudyFileStopsBeforeAnyTask) {
  const std::string dir = test::scratch_dir("study_bad");
  const std::string scene = test::source_path("runs/scenes/bratu1d_fold.toml");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[study]\nscene = \"" + scene + "\"\nwhat = 1\n", "bad.toml:3: unknown key 'study.what'"},
      {"[study]\nscene = \"" + scene + "\"\n[grid]\n\"bratu.intervals\" = [16, 1]\n",
       "bad.toml: task 1 (bratu.intervals=1): " + scene + " (--set): key 'bratu.intervals' = 1 is out of range"},
      {"[study]\nscene = \"" + scene + "\"\n[set]\n\"bratu.nope\" = 1\n", "unknown key 'bratu.nope'"},
      {"[study]\nscene = \"" + scene + "\"\n[grid]\n\"bratu.intervals\" = 16\n",
       "bad.toml:4: [grid] key 'bratu.intervals' must be a non-empty list"},
      {"[study]\nscene = \"" + scene + "\"\n[solve]\n", "bad.toml:3: unknown section [solve]"},
      {"[study]\ntask = \"trace\"\n", "key 'study.scene' (the base scene) is missing"},
      // names the tasks' branch files will not have: found before any task runs
      {"[study]\nscene = \"" + scene + "\"\n[collect]\nstops = [\"u_mdi\"]\n",
       "bad.toml: [collect] stops names 'u_mdi', which task 0 (the base scene) will not have; its observables: "},
      {"[study]\nscene = \"" + scene +
           "\"\n[grid]\n\"bratu.intervals\" = [16, 24]\n[collect]\nevents = "
           "[\"fold\", \"u_top\"]\n",
       "bad.toml: [collect] events names 'u_top', which task 0 (bratu.intervals=16) will not have; events are fold, "
       "branch-point, hopf, a monitor"},
      {"[study]\nscene = \"" + scene + "\"\n[collect]\nend = [\"u_mid\", \"sigma1_re\"]\n",
       "[collect] end names 'sigma1_re'"},  // (a stability column, without stability)
      // an observable that is not the stop observable (u_mid) has no located zero, and no threshold
      {"[study]\nscene = \"" + scene + "\"\n[collect]\nevents = [\"u_max\"]\n",
       "[collect] events names 'u_max', which task 0 (the base scene) will not have; events are fold, branch-point, "
       "hopf, a monitor (u_mid > stop_above) or the stop observable (u_mid)"},
      {"[study]\nscene = \"" + scene + "\"\n[collect]\nend = [\"monitor:u_max > stop_above\"]\n",
       "[collect] end names 'monitor:u_max > stop_above'"},
  };
  for (const auto& [text, expected] : cases) {
    SCOPED_TRACE(text);
    std::ofstream(dir + "/bad.toml") << text;
    const auto r = test::run_keller("study " + dir + "/bad.toml -o " + dir + "/out");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/out"));
  }
}

// Issue 19, item 5: a Wi branch of the collapsible channel started from the stored state of a
// Gamma branch at Gamma = 1.98e-4 is, to the corrector's tolerance, the Wi branch started from a
// fresh solve at the same parameters (coarse mesh).
TEST(Study, ABranchInAnotherParameterFromAStoredPointIsTheBranchFromAFreshSolve) {
  const std::string dir = test::scratch_dir("study_other_parameter");
  const std::string coarse =
      " --set mesh.name=custom --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set mesh.nx_downstream=5"
      " --set mesh.ny_fluid=4 --set mesh.ny_solid=2 --set output.xdmf=false";
  auto r =
      test::run_keller("trace " + test::source_path("runs/scenes/collapsible_oldroyd_b_gamma.toml") + coarse +
                       " --set parameters.Wi=0.02 --set continuation.upper=2.5e-4 --set 'continuation.stops=[1.98e-4]'"
                       " -o " +
                       dir + "/gamma.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable g = read_branch_table(dir + "/gamma.h5");
  int row = -1;
  for (long i = 0; i < g.rows.rows(); ++i)
    if (static_cast<int>(g.rows(i, g.column("kind"))) == 2) row = static_cast<int>(i);
  ASSERT_GE(row, 0);
  ASSERT_NEAR(g.rows(row, g.column("Gamma")), 1.98e-4, 1e-12);
  const std::string wi =
      test::source_path("runs/scenes/collapsible_oldroyd_b_wi_low_gamma.toml") + coarse +
      " --set parameters.Gamma=1.98e-4 --set continuation.upper=0.06 --set 'continuation.stops=[0.03,0.05]'";
  r = test::run_keller("trace " + wi + " -o " + dir + "/from_gamma.h5 --restart " + dir +
                       "/gamma.h5:" + std::to_string(row));
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("starting a branch in Wi at row"), std::string::npos) << r.out;
  r = test::run_keller("trace " + wi + " --set parameters.Wi=0.02 -o " + dir + "/fresh.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable a = read_branch_table(dir + "/from_gamma.h5"), b = read_branch_table(dir + "/fresh.h5");
  EXPECT_NEAR(a.rows(0, a.column("Wi")), 0.02, 1e-15);
  // the points every run of this scene lands on: the stops and the end
  auto landed = [](const BranchTable& t) {
    std::vector<long> rows;
    for (long i = 0; i < t.rows.rows(); ++i)
      if (const int k = static_cast<int>(t.rows(i, t.column("kind"))); k == 2 || k == 6 || i == 0) rows.push_back(i);
    return rows;
  };
  const auto ra = landed(a), rb = landed(b);
  ASSERT_EQ(ra.size(), rb.size());
  ASSERT_GE(ra.size(), 3u);
  for (size_t k = 0; k < ra.size(); ++k)
    for (const std::string c : {"Wi", "dP", "dy_max", "gap_min", "min_m1", "max_m3"}) {
      const double x = a.rows(ra[k], a.column(c)), y = b.rows(rb[k], b.column(c));
      // both solutions meet the corrector's residual tolerance (1e-10 relative): the observables
      // agree to about that times the conditioning
      EXPECT_NEAR(x, y, 1e-7 * std::max(1.0, std::abs(y))) << c << " at landed point " << k;
    }
}

// What accuracy costs (runs/scripts/convergence.py) on a family with a known limit: the fold of
// the 1D Bratu problem on 16 to 128 intervals converges at second order, and the Richardson
// extrapolation of the two finest grids lands on the continuum fold 3.513830719125 to within its
// h^4 remainder (3e-8 here; 1e-7 relative asserted). Each family is the same grid traced with a
// different first and largest step (two group keys, whose group name holds a comma in the CSV):
// the located fold does not depend on the steps, so every family has the same order and limit.
TEST(Study, TheConvergenceTableFindsTheOrderAndTheLimit) {
  const std::string dir = test::scratch_dir("study_convergence");
  const std::string study = dir + "/conv.toml";
  std::ofstream(study) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml") << "\"\n"
                       << "[set]\n\"output.xdmf\" = false\n[grid]\n\"bratu.intervals\" = [16, 32, 64, 128]\n"
                       << "\"continuation.initial_step\" = [0.05, 0.1]\n\"continuation.max_step\" = [0.3, 0.6]\n"
                       << "[collect]\nevents = [\"fold\"]\n";
  auto r = test::run_keller("study " + study + " --jobs 2 -o " + dir + "/conv");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string script = std::string(KELLER_PYTHON) + " " + test::source_path("runs/scripts/convergence.py") + " " +
                             dir +
                             "/conv/conv.h5 --mesh bratu.intervals --resolution bratu.intervals --group "
                             "continuation.initial_step continuation.max_step --observables "
                             "event:fold --published event:fold=3.513830719125 --csv " +
                             dir + "/conv.csv --markdown " + dir + "/conv.md --figure " + dir + "/conv.png > /dev/null";
  ASSERT_EQ(std::system(script.c_str()), 0);
  const auto rows = test::read_table(dir + "/conv.csv");
  ASSERT_EQ(rows.size(), 16u);
  std::map<std::string, std::vector<double>> errors;  // per family, the grids in order
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("observed"), "True");
    EXPECT_NEAR(std::stod(row.at("order")), 2.0, 0.01);
    EXPECT_NEAR(std::stod(row.at("extrapolated")), 3.513830719125, 1e-7 * 3.513830719125);
    errors[row.at("group")].push_back(std::stod(row.at("error")));
  }
  ASSERT_EQ(errors.size(), 4u);
  EXPECT_TRUE(errors.count("continuation.initial_step = 0.05, continuation.max_step = 0.3"))
      << test::file_contents(dir + "/conv.csv");
  // the error of each grid against the extrapolation falls fourfold per halving of h
  for (const auto& [group, e] : errors) {
    ASSERT_EQ(e.size(), 4u) << group;
    for (size_t k = 1; k < e.size(); ++k) EXPECT_NEAR(e[k - 1] / e[k], 4.0, 0.05) << group;
  }
  EXPECT_TRUE(fs::exists(dir + "/conv.png"));
  EXPECT_NE(test::file_contents(dir + "/conv.md").find("| event:fold | 128 |"), std::string::npos);
}

// The BLAS threads of a worker: the cores shared among the workers, never fewer than one, and
// never more than a limit the user set in OPENBLAS_NUM_THREADS (a malformed or non-positive
// setting is no limit).
TEST(Study, BlasThreadsShareTheCoresAndKeepTheUsersLimit) {
  EXPECT_EQ(blas_threads_for(1, 8, nullptr), 8);
  EXPECT_EQ(blas_threads_for(3, 8, nullptr), 2);
  EXPECT_EQ(blas_threads_for(16, 8, nullptr), 1);
  EXPECT_EQ(blas_threads_for(0, 8, nullptr), 8);
  EXPECT_EQ(blas_threads_for(1, 8, "1"), 1);
  EXPECT_EQ(blas_threads_for(2, 8, "3"), 3);
  EXPECT_EQ(blas_threads_for(2, 8, "16"), 4);
  for (const char* bad : {"", "0", "-2", "two", "2x"}) EXPECT_EQ(blas_threads_for(2, 8, bad), 4) << bad;
}

// Every shipped study (runs/studies/, runs/paper/) resolves each of its tasks as `--set` would
// (`keller study list` validates every override before it lists) and has the number of tasks
// docs/studies/README.md gives it: a scene key renamed or a grid edited without the docs fails here.
TEST(Study, EveryShippedStudyResolvesItsTasksAsDocumented) {
  const std::string readme = test::file_contents(test::source_path("docs/studies/README.md"));
  const std::regex row(R"(\| `runs/(studies/[a-z_]+\.toml|paper/\*\.toml)` \| (\d+) \|)");
  std::map<std::string, int> documented;
  for (std::sregex_iterator it(readme.begin(), readme.end(), row), end; it != end; ++it)
    documented[(*it)[1]] = std::stoi((*it)[2]);
  ASSERT_GE(documented.size(), 2u) << "the table of shipped studies in docs/studies/README.md";
  const std::string dir = test::scratch_dir("study_shipped");
  int paper_tasks = 0;
  std::set<std::string> listed;
  for (const char* folder : {"runs/studies", "runs/paper"}) {
    for (const auto& entry : fs::directory_iterator(test::source_path(folder))) {
      if (entry.path().extension() != ".toml") continue;
      const std::string name = std::string(folder).substr(5) + "/" + entry.path().filename().string();
      SCOPED_TRACE(name);
      const auto r = test::run_keller("study list " + entry.path().string() + " -o " + dir + "/out");
      ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
      std::smatch m;
      ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(^# (\d+) tasks of )"))) << r.out;
      const int tasks = std::stoi(m[1]);
      EXPECT_EQ(count(r.out, " missing "), tasks) << r.out;  // nothing run: every task missing
      if (name.rfind("paper/", 0) == 0) {
        paper_tasks += tasks;
      } else {
        listed.insert(name);
        ASSERT_TRUE(documented.count(name)) << "not in docs/studies/README.md";
        EXPECT_EQ(tasks, documented[name]);
      }
    }
  }
  EXPECT_EQ(paper_tasks, documented["paper/*.toml"]);
  for (const auto& [name, tasks] : documented) {
    if (name != "paper/*.toml") {
      EXPECT_TRUE(listed.count(name)) << name << " is documented but not shipped";
    }
  }
  EXPECT_FALSE(fs::exists(dir + "/out"));  // listing writes nothing
}

// Names of every kind a branch table has pass the check: an observable, the parameter, the stop's
// threshold monitor, a column of the engine's, the stability columns where stability is on, the
// stop observable as an event.
TEST(Study, TheCollectCheckTakesEveryColumnABranchTableHas) {
  const std::string dir = test::scratch_dir("study_collect_names");
  const std::string path = dir + "/names.toml";
  std::ofstream(path) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml")
                      << "\"\n[set]\n\"stability.enabled\" = true\n\"stability.count\" = 2\n[collect]\n"
                      << "events = [\"fold\", \"u_mid\", \"branch-point\"]\n"
                      << "stops = [\"u_max\", \"monitor:u_mid > stop_above\", \"det_sign\", \"sigma2_re\"]\n"
                      << "end = [\"lambda\", \"unstable\", \"tangent_parameter\"]\n";
  const Study study = Study::load(path, dir + "/out");
  EXPECT_NO_THROW(study.check_collect());
  // sigma3_re: beyond stability.count
  std::ofstream(path) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml")
                      << "\"\n[set]\n\"stability.enabled\" = true\n\"stability.count\" = 2\n[collect]\n"
                      << "end = [\"sigma3_re\"]\n";
  EXPECT_THROW(Study::load(path, dir + "/out").check_collect(), SceneError);
}

// What every shipped study's [collect] names is in its tasks' outputs (the check a study run makes
// before its first task; a renamed observable fails here, not after hours of tasks).
TEST(Study, EveryShippedStudyCollectsNamesItsTasksHave) {
  const std::string dir = test::scratch_dir("study_shipped_collect");
  int studies = 0;
  for (const char* folder : {"runs/studies", "runs/paper"})
    for (const auto& entry : fs::directory_iterator(test::source_path(folder))) {
      if (entry.path().extension() != ".toml") continue;
      SCOPED_TRACE(entry.path().string());
      const Study study = Study::load(entry.path().string(), dir + "/out");
      EXPECT_NO_THROW(study.check_collect());
      ++studies;
    }
  EXPECT_GE(studies, 5);
}

// A requested stop on the bound where the branch ends is written as the end row; the study still
// collects it as that stop (the cylinder's accuracy study stops at Wi = 0.9, its upper bound).
TEST(Study, AStopOnTheBoundWhereTheBranchEndsIsCollected) {
  const std::string dir = test::scratch_dir("study_stop_on_bound");
  const std::string study = dir + "/bound.toml";
  std::ofstream(study) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml") << "\"\n"
                       << "[set]\n\"output.xdmf\" = false\n\"continuation.upper\" = 2.0\n"
                       << "[grid]\n\"bratu.intervals\" = [16, 32]\n[collect]\nstops = [\"u_mid\"]\nend = [\"u_mid\"]\n";
  const auto r = test::run_keller("study " + study + " -o " + dir + "/bound");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto rows = test::read_table(dir + "/bound/bound.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows) {
    EXPECT_EQ(std::stod(row.at("end_parameter")), 2.0);
    ASSERT_TRUE(row.count("u_mid@2")) << "no column u_mid@2";
    EXPECT_EQ(row.at("u_mid@2"), row.at("end:u_mid"));  // the same row
    EXPECT_GT(std::stod(row.at("u_mid@1")), 0.0);
    EXPECT_LT(std::stod(row.at("u_mid@1")), std::stod(row.at("u_mid@2")));  // u grows with lambda below the fold
    EXPECT_FALSE(row.count("u_mid@3"));                                     // beyond the bound: not reached, no column
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
// study add up both runs (the first run's cost is kept in the unfinished output, /cost): its
// points are the rows of the branch, once each (the continued run's first row is the first run's
// last), its factorisations and seconds those of both runs' summaries.
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
  EXPECT_NEAR(std::stod(row.at("seconds")), seconds, 0.01);  // (the log's to 2 decimals)
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
    const auto signalled = std::chrono::steady_clock::now();
    int status = 0;
    waitpid(pid, &status, 0);
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    EXPECT_LT(waited, 1.0);  // a point takes about 10 ms; the whole branch about 2 s
    const auto row = test::read_table(dir + "/s/long.csv").at(0);
    EXPECT_EQ(row.at("status"), "interrupted");
    ASSERT_TRUE(fs::exists(part));
    const long kept = read_branch_table(part).rows.rows();
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

namespace {

// A study of `n` x 100 tasks over the steps of a 16-interval Bratu branch (each about 0.1 s).
std::string many_tasks_study(const std::string& dir, int n) {
  const std::string path = fmt::format("{}/many{}.toml", dir, n);
  std::ofstream f(path);
  f << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml") << "\"\n"
    << "[set]\n\"bratu.intervals\" = 16\n\"output.xdmf\" = false\n[grid]\n\"continuation.max_step\" = [";
  for (int i = 0; i < n; ++i) f << (i ? ", " : "") << fmt::format("{:.4f}", 0.3 + 1e-4 * i);
  f << "]\n\"continuation.initial_step\" = [";
  for (int i = 0; i < 100; ++i) f << (i ? ", " : "") << fmt::format("{:.4f}", 0.05 + 1e-4 * i);
  f << "]\n";
  return path;
}

double seconds_of(const std::function<void()>& run) {
  const auto t0 = std::chrono::steady_clock::now();
  run();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// Issue 30, item 12: a task's process does not check every task of its study again (it did: each
// of a study's N tasks cost N scene validations, minutes per task for 10^6 tasks): a task of a
// 20000-task study runs about as fast as the same task of a 100-task study (a validation costs
// about 0.25 ms: 5 s for the study). Checking all of a large study's tasks (`study`, `list`,
// `collect`) says so on the terminal, with the time it took.
TEST(Study, ATaskOfALargeStudyDoesNotCheckEveryTaskAgain) {
  const std::string dir = test::scratch_dir("study_large");
  const std::string small = many_tasks_study(dir, 1), large = many_tasks_study(dir, 200);
  test::CommandResult r;
  const double alone = seconds_of([&] { r = test::run_keller("study run " + small + " --task 0 -o " + dir + "/a"); });
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const double among = seconds_of([&] { r = test::run_keller("study run " + large + " --task 0 -o " + dir + "/b"); });
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_LT(among, alone + 1.0) << "the task alone " << alone << " s, among 20000: " << among << " s";
  r = test::run_keller("study list " + large + " -o " + dir + "/b");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("checking the 20000 tasks of "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("checked 20000 tasks in "), std::string::npos) << r.err;
  EXPECT_EQ(count(r.out, " done "), 1);
  EXPECT_EQ(count(r.out, " missing "), 19999);
}

// Issue 30, item 12: tasks that resolve to the same run (values written 1 and 1.0; a case that
// sets a key to its default beside one that does not set it) are refused before any task runs,
// naming both; a task does not check the others, but its own study file must be valid.
TEST(Study, TasksThatResolveToTheSameRunAreRefused) {
  const std::string dir = test::scratch_dir("study_same_run");
  const std::string scene = test::source_path("runs/scenes/bratu1d_fold.toml");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[study]\nscene = \"" + scene + "\"\n[grid]\n\"continuation.max_step\" = [0.5, 1, 1.0]\n",
       "dup.toml: task 2 (continuation.max_step=1.0) is the same run as task 1 (continuation.max_step=1): every "
       "key resolves to the same value"},
      {"[study]\nscene = \"" + scene +
           "\"\n[[cases]]\n\"bratu.intervals\" = 16\n[[cases]]\n\"bratu.intervals\" = "
           "16\n\"bratu.lambda\" = 0.0\n",
       "dup.toml: task 1 (bratu.intervals=16, bratu.lambda=0.0) is the same run as task 0 (bratu.intervals=16)"},
  };
  for (const auto& [text, expected] : cases) {
    SCOPED_TRACE(text);
    std::ofstream(dir + "/dup.toml") << text;
    for (const std::string command : {"study", "study list", "study collect"}) {
      const auto r = test::run_keller(command + " " + dir + "/dup.toml -o " + dir + "/out");
      EXPECT_EQ(r.exit_code, 2) << command << ": " << r.out;
      EXPECT_NE(r.err.find(expected), std::string::npos) << command << ": " << r.err;
    }
    EXPECT_FALSE(fs::exists(dir + "/out"));
  }
}
