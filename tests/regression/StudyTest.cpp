// keller study end to end: the same collected table under every executor (one worker, two, the
// ranks of mpirun); a task that fails is recorded with its reason while the others complete; a
// bad study file stops before any task; and a branch started from a stored point of a branch in
// another parameter is the branch started from a fresh solve there. Issue 30: a task's process
// checks its task alone; tasks that resolve to the same run are refused. (Studies after damage
// and interruptions: StudyDamageTest.cpp.)
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>

#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "runs/OutputFile.hpp"
#include "runs/study/StudyRunner.hpp"
#include "support/StudySupport.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
using test::bratu_study;
using test::count;
using test::table_without_time;
namespace fs = std::filesystem;

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
    // the cost of the linear algebra: J (tridiagonal, m = n - 1 unknowns) factorised on its own by
    // the block elimination: nnz(L + U) = nnz(J) = 3 m - 2, plus the few entries row exchanges
    // add where MUMPS pivots off the diagonal (J indefinite past the fold: 2 in the 32-interval
    // branch whose last factorisation lies there, 93 for 91), far below the bordered matrix's,
    // whose dense row and column would add 2 m; a solve per corrector iteration at least
    const double m = std::stod(row.at("bratu.intervals")) - 1;
    EXPECT_GE(std::stod(row.at("nnz_lu")), 3 * m - 2) << row.at("name");
    EXPECT_LE(std::stod(row.at("nnz_lu")), 3 * m - 2 + 4) << row.at("name");
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

// What accuracy costs (python3 -m keller.convergence) on a family with a known limit: the fold of
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
  const std::string script = test::python_module("keller.convergence") + " " + dir +
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

}  // namespace

// Issue 30, item 12: a task's process does not check every task of its study again (it did: each
// of a study's N tasks cost N scene validations, minutes per task for 10^6 tasks): a task of a
// 20000-task study runs without the check of the whole study (which says so on the terminal),
// and a task runs where another task of its study would stop the study. Checking all of a large
// study's tasks (`study`, `list`, `collect`) says so on the terminal, with the time it took.
TEST(Study, ATaskOfALargeStudyDoesNotCheckEveryTaskAgain) {
  const std::string dir = test::scratch_dir("study_large");
  const std::string large = many_tasks_study(dir, 200);
  auto r = test::run_keller("study run " + large + " --task 0 -o " + dir + "/b");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(r.err.find("checking the"), std::string::npos) << r.err;
  const std::string other_refused = dir + "/other.toml";  // task 1 out of range
  std::ofstream(other_refused) << "[study]\nscene = \"" << test::source_path("runs/scenes/bratu1d_fold.toml")
                               << "\"\n[set]\n\"output.xdmf\" = false\n[grid]\n\"bratu.intervals\" = [16, 1]\n";
  r = test::run_keller("study run " + other_refused + " --task 0 -o " + dir + "/o");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  r = test::run_keller("study " + other_refused + " -o " + dir + "/o");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("task 1 (bratu.intervals=1)"), std::string::npos) << r.err;
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
