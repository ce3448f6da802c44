// keller trace end to end: scenes against their checked-in references, CSV export, the figure
// script, restarts that reproduce the original run, a run killed by SIGKILL that leaves a
// readable file, and bad continuation input.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

struct SceneCase {
  std::string scene;
  std::vector<std::string> overrides;
};

std::vector<SceneCase> regression_scenes() {
  std::ifstream in(test::source_path("tests/regression/scenes.txt"));
  std::vector<SceneCase> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto bar = line.find('|');
    SceneCase c;
    std::istringstream scene(line.substr(0, bar));
    scene >> c.scene;
    if (bar != std::string::npos) {
      std::istringstream ov(line.substr(bar + 1));
      std::string o;
      while (ov >> o) c.overrides.push_back(o);
    }
    out.push_back(c);
  }
  return out;
}

std::string set_args(const std::vector<std::string>& overrides) {
  std::string s;
  for (const auto& o : overrides) s += " --set " + o;
  return s;
}

// CSV with a header line: returns columns and rows.
std::pair<std::vector<std::string>, std::vector<std::vector<double>>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> cols;
  std::vector<std::vector<double>> rows;
  std::getline(in, line);
  std::stringstream h(line);
  std::string c;
  while (std::getline(h, c, ',')) cols.push_back(c);
  while (std::getline(in, line)) {
    std::stringstream r(line);
    std::vector<double> row;
    while (std::getline(r, c, ',')) row.push_back(std::stod(c));
    rows.push_back(row);
  }
  return {cols, rows};
}

// The same, every cell as its text.
std::pair<std::vector<std::string>, std::vector<std::vector<std::string>>> read_csv_cells(const std::string& path) {
  std::ifstream in(path);
  std::string line, c;
  std::vector<std::string> cols;
  std::vector<std::vector<std::string>> rows;
  std::getline(in, line);
  std::stringstream h(line);
  while (std::getline(h, c, ',')) cols.push_back(c);
  while (std::getline(in, line)) {
    std::stringstream r(line);
    std::vector<std::string> row;
    while (std::getline(r, c, ',')) row.push_back(c);
    rows.push_back(row);
  }
  return {cols, rows};
}

}  // namespace

TEST(Trace, ScenesMatchTheirReferences) {
  const std::string dir = test::scratch_dir("trace_ref");
  for (const SceneCase& c : regression_scenes()) {
    SCOPED_TRACE(c.scene);
    const std::string name = fs::path(c.scene).stem().string();
    const std::string out = dir + "/" + name + ".h5";
    const auto r = test::run_keller("trace " + test::source_path(c.scene) + " -o " + out + set_args(c.overrides));
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    const BranchTable t = read_branch_table(out);
    const auto [ref_cols, ref_rows] = read_csv(test::source_path("tests/regression/references/" + name + ".csv"));
    // located rows of this run
    std::vector<int> located;
    for (long i = 0; i < t.rows.rows(); ++i)
      if (t.rows(i, t.column("kind")) != 0.0 && t.rows(i, t.column("kind")) != 1.0)
        located.push_back(static_cast<int>(i));
    ASSERT_EQ(located.size(), ref_rows.size()) << "number of located points changed";
    for (size_t k = 0; k < ref_rows.size(); ++k) {
      const bool fold = ref_rows[k][0] == 4.0;
      for (size_t j = 0; j < ref_cols.size(); ++j) {
        const double got = t.rows(located[k], t.column(ref_cols[j])), want = ref_rows[k][j];
        // Located points are converged to 1e-10 in the parameter and to Newton's tolerance in
        // the state: 1e-7 relative leaves room for rounding differences between machines and
        // BLAS. At a fold the parameter varies quadratically along the branch, so the state there
        // is only fixed to about the square root of the parameter tolerance: 1e-5.
        const double rel = fold && ref_cols[j] != t.parameter ? 1e-5 : 1e-7;
        EXPECT_NEAR(got, want, rel * std::max(1.0, std::abs(want))) << ref_cols[j] << " of located point " << k;
      }
    }
    EXPECT_NE(t.status, "running");
  }
}

TEST(Trace, ExportCsvAndFigure) {
  const std::string dir = test::scratch_dir("trace_export");
  auto r = test::run_keller("trace " + test::source_path("runs/scenes/bratu1d_fold.toml") + " -o " + dir +
                            "/b.h5 --set bratu.intervals=32");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("fold max"), std::string::npos);  // progress lines name located points
  EXPECT_NE(r.out.find("|F|"), std::string::npos);       // and show the corrector's residual
  r = test::run_keller("export " + dir + "/b.h5 --csv " + dir + "/b.csv");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto [cols, rows] = read_csv_cells(dir + "/b.csv");
  const BranchTable t = read_branch_table(dir + "/b.h5");
  EXPECT_EQ(cols, t.columns);
  ASSERT_EQ(static_cast<long>(rows.size()), t.rows.rows());
  // the kind by its name (the HDF5 table keeps the number), every other value to all its digits
  const std::vector<std::string> names = {"point", "start", "stop", "event", "fold", "bp", "end", "hopf"};
  std::map<std::string, int> kinds;
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = 0; j < cols.size(); ++j) {
      const double v = t.rows(static_cast<long>(i), static_cast<long>(j));
      if (cols[j] == "kind") {
        EXPECT_EQ(rows[i][j], names.at(static_cast<size_t>(v))) << "row " << i;
        ++kinds[rows[i][j]];
      } else {
        EXPECT_EQ(std::stod(rows[i][j]), v) << cols[j] << " of row " << i;
      }
    }
  EXPECT_EQ(kinds["start"], 1);
  EXPECT_EQ(kinds["fold"], 1);  // Bratu's one fold, at lambda = 3.51
  EXPECT_EQ(kinds["end"], 1);
  const std::string cmd =
      test::python_module("keller.plot branch") + " " + dir + "/b.h5 --y u_mid -o " + dir + "/b.png > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_GT(fs::file_size(dir + "/b.png"), 10000u);
}

// A finished trace writes the fields of its stored solutions and an XDMF time series; keller
// export --xdmf rebuilds the problem from the scene stored in the file and does the same.
TEST(Trace, FieldsAndXdmfOfStoredSolutions) {
  const std::string dir = test::scratch_dir("trace_xdmf");
  auto r = test::run_keller("trace " + test::source_path("runs/scenes/bratu2d_fold.toml") + " -o " + dir +
                            "/b.h5 --set bratu.intervals=4");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(dir + "/b.xdmf"));
  {
    H5File f(dir + "/b.h5", H5File::Mode::ReadWrite);  // closed cleanly: opens for writing
    EXPECT_TRUE(f.exists("/branch/fields/0/u"));
    EXPECT_TRUE(f.exists("/mesh/nodes"));
  }
  fs::remove(dir + "/b.xdmf");
  r = test::run_keller("export " + dir + "/b.h5 --xdmf");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream x(dir + "/b.xdmf");
  const std::string xdmf((std::istreambuf_iterator<char>(x)), std::istreambuf_iterator<char>());
  EXPECT_NE(xdmf.find("CollectionType=\"Temporal\""), std::string::npos);
  EXPECT_NE(xdmf.find("b.h5:/branch/fields/0/xdmf/nodes"), std::string::npos);
}

TEST(Trace, RestartReproducesTheOriginalRun) {
  const std::string dir = test::scratch_dir("trace_restart");
  const std::string scene = test::source_path("runs/scenes/bratu1d_fold.toml");
  // the Newton corrector, whose steps depend only on the stored point: the restart then repeats
  // the original run's arithmetic (a chord on a kept factorisation depends on where that was made,
  // which a restart cannot know: its points agree to the corrector's tolerance instead)
  const std::string common =
      " --set bratu.intervals=64 --set continuation.save_every=1"
      " --set continuation.corrector=newton --set continuation.bordered=full";
  auto r = test::run_keller("trace " + scene + " -o " + dir + "/a.h5" + common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const int from = 6;
  r = test::run_keller("trace " + scene + " -o " + dir + "/b.h5 --restart " + dir + "/a.h5:" + std::to_string(from) +
                       common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable a = read_branch_table(dir + "/a.h5"), b = read_branch_table(dir + "/b.h5");
  ASSERT_GT(b.rows.rows(), 8);
  ASSERT_EQ(a.rows.rows(), from + b.rows.rows());  // the same branch, to the same end
  for (const char* col : {"lambda", "s", "u_mid", "u_max"}) {
    for (long i = 0; i < b.rows.rows(); ++i) {
      const double va = a.rows(from + i, a.column(col)), vb = b.rows(i, b.column(col));
      EXPECT_NEAR(vb, va, 1e-10 * std::max(1.0, std::abs(va))) << col << " at restart row " << i;
    }
  }
  // a row without a stored solution cannot be restarted from, and the message lists those that can
  r = test::run_keller("trace " + scene + " -o " + dir + "/c.h5 --restart " + dir + "/a.h5:999" + common);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("has no stored solution; stored rows: 0, 1, 2"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/c.h5"));
}

// keller trace --switch: the pitchfork scene finds the first branch point by its eigenvalue
// (stored with its critical eigenvector, the null vector of J: sin(pi x)); switching there
// follows the bifurcated branch (u not 0, stable, lambda above lambda_1 as the pitchfork is
// supercritical). Both diagrams draw with the figure script.
TEST(Trace, SwitchAtABranchPointFollowsTheBifurcatedBranch) {
  const std::string dir = test::scratch_dir("trace_switch");
  const std::string scene = test::source_path("runs/scenes/pitchfork1d_trivial.toml");
  const std::string common = " --set pitchfork.intervals=32";
  auto r = test::run_keller("trace " + scene + " -o " + dir + "/a.h5" + common);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable a = read_branch_table(dir + "/a.h5");
  long bp = -1;
  for (long i = 0; i < a.rows.rows() && bp < 0; ++i)
    if (a.rows(i, a.column("kind")) == static_cast<double>(PointKind::BranchPoint)) bp = i;
  ASSERT_GE(bp, 0);
  const double lambda1 = a.rows(bp, a.column("lambda"));
  EXPECT_NEAR(lambda1, 4.0 * 32 * 32 * std::pow(std::sin(M_PI / 64.0), 2), 1e-8);
  {
    H5File f(dir + "/a.h5", H5File::Mode::Read);
    ASSERT_TRUE(f.exists("/branch/eigenvectors"));
    long rows = 0, cols = 0, er = 0, ec = 0;
    const std::vector<double> data = f.read_matrix("/branch/eigenvectors", &rows, &cols);
    const std::vector<double> which = f.read_matrix("/branch/eigenvector_rows", &er, &ec);
    long k = -1;  // the branch point's entry (stored solutions have theirs too)
    for (long i = 0; i < er; ++i)
      if (which[static_cast<size_t>(i * ec)] == static_cast<double>(bp)) k = i;
    ASSERT_GE(k, 0);
    ASSERT_GE(rows, 2 * k + 2);  // real and imaginary part of each stored eigenvector
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> all(data.data(),
                                                                                                       rows, cols);
    const Eigen::MatrixXd v = all.middleRows(2 * k, 2);
    // sin(pi x_i), up to sign and scale
    Eigen::VectorXd phi = v.row(0).transpose(), sine(phi.size());
    for (int i = 0; i < sine.size(); ++i) sine[i] = std::sin(M_PI * (i + 1) / 32.0);
    const double c = phi.dot(sine) / sine.squaredNorm();
    EXPECT_LT((phi - c * sine).norm(), 1e-8 * phi.norm());
    EXPECT_LT(v.row(1).norm(), 1e-12);
  }
  r = test::run_keller("trace " + scene + " -o " + dir + "/b.h5 --switch " + dir + "/a.h5:" + std::to_string(bp) +
                       common + " --set continuation.upper=20");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("switching branches at row " + std::to_string(bp)), std::string::npos) << r.out;
  const BranchTable b = read_branch_table(dir + "/b.h5");
  ASSERT_GT(b.rows.rows(), 5);
  for (long i = 1; i < b.rows.rows(); ++i) {
    EXPECT_GT(b.rows(i, b.column("u_norm")), 1e-3) << "row " << i;
    EXPECT_GT(b.rows(i, b.column("lambda")), lambda1 - 1e-8) << "row " << i;
    EXPECT_EQ(b.rows(i, b.column("unstable")), 0.0) << "row " << i;
  }
  const std::string cmd = test::python_module("keller.plot branch") + " " + dir + "/a.h5 " + dir +
                          "/b.h5 --y u_quarter -o " + dir + "/ab.png > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_GT(fs::file_size(dir + "/ab.png"), 10000u);
  // --switch and --restart exclude each other
  r = test::run_keller("trace " + scene + " -o " + dir + "/c.h5 --switch " + dir + "/a.h5:" + std::to_string(bp) +
                       " --restart " + dir + "/a.h5:0" + common);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir + "/c.h5"));
}

// The collapsible channel with [stability]: the critical eigenvector of each stored solution goes
// to the branch file and, as fields (the linear change along it, on the deformed mesh), to an
// XDMF file per mode that ParaView opens.
TEST(Trace, CollapsibleEigenmodesAsFields) {
  const std::string dir = test::scratch_dir("trace_modes");
  auto r =
      test::run_keller("trace " + test::source_path("runs/scenes/collapsible_oldroyd_b_gamma.toml") + " -o " + dir +
                       "/c.h5 --set mesh.name=custom --set mesh.nx_upstream=3 --set mesh.nx_deformable=6"
                       " --set mesh.nx_downstream=3 --set mesh.ny_fluid=3 --set mesh.ny_solid=1"
                       " --set stability.enabled=true --set continuation.max_steps=1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(fs::exists(dir + "/c_mode0.xdmf"));
  H5File f(dir + "/c.h5", H5File::Mode::Read);
  EXPECT_TRUE(f.exists("/branch/modes/0/re/velocity"));
  EXPECT_TRUE(f.exists("/branch/modes/0/mesh/nodes"));
  long er = 0, ec = 0;
  const std::vector<double> rows = f.read_matrix("/branch/eigenvector_rows", &er, &ec);
  ASSERT_GE(er, 1);
  EXPECT_EQ(rows[0], 0.0);  // the start (a stored solution)
  EXPECT_GT(rows[2], 0.0);  // Re sigma of its critical eigenvalue: stable
  const BranchTable t = read_branch_table(dir + "/c.h5");
  EXPECT_EQ(t.rows(0, t.column("unstable")), 0.0);
  EXPECT_LT(t.rows(0, t.column("eig_residual")), 1e-8);
}

namespace {

// Kills `keller trace` with SIGKILL once `rows` points are on disk (0: a few milliseconds after
// it starts) and checks what is left: nothing under the branch file's name, and no unfinished
// file or one (OUT.h5.part) that opens with every completed point.
void kill_and_check(const std::string& dir, int rows_before_kill) {
  SCOPED_TRACE("kill after " + std::to_string(rows_before_kill) + " rows");
  const std::string out = dir + "/k" + std::to_string(rows_before_kill) + ".h5";
  const std::string work = out + ".part";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (!freopen("/dev/null", "w", stdout)) _exit(3);
    const std::string scene = test::source_path("runs/scenes/bratu2d_fold.toml");
    execl(KELLER_BINARY, "keller", "trace", scene.c_str(), "-o", out.c_str(), "--set", "bratu.intervals=16", "--set",
          "continuation.max_step=0.002", "--set", "continuation.initial_step=0.002", "--set",
          "continuation.max_steps=100000", "--set", "continuation.save_every=3", static_cast<char*>(nullptr));
    _exit(127);
  }
  long rows = 0;
  const auto t0 = std::chrono::steady_clock::now();
  if (rows_before_kill == 0) std::this_thread::sleep_for(std::chrono::milliseconds(15));
  while (rows < rows_before_kill && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    try {
      rows = read_branch_table(work).rows.rows();
    } catch (const std::exception&) {  // not there yet
    }
  }
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the run ended before it was killed";
  ASSERT_GE(rows, rows_before_kill) << "no points appeared in time";
  EXPECT_FALSE(fs::exists(out));  // the name is taken only by a branch that ended
  if (!fs::exists(work)) {
    EXPECT_EQ(rows_before_kill, 0);  // killed before the branch file was ready
    return;
  }
  const BranchTable t = read_branch_table(work);
  EXPECT_GE(t.rows.rows(), rows);  // every point completed before the kill is there
  EXPECT_TRUE(t.rows.allFinite());
  EXPECT_EQ(t.status, "running");  // it never finished
  for (long i = 0; i < t.rows.rows(); ++i) EXPECT_EQ(t.rows(i, t.column("row")), static_cast<double>(i));
  if (t.rows.rows() > 0) {
    const BranchPoint last = read_branch_point(work, -1);  // the last stored solution is usable
    EXPECT_TRUE(last.u.allFinite());
    EXPECT_GT(last.u.size(), 0);
  }
  // keller export reads the killed file too
  const auto r = test::run_keller("export " + work + " --csv " + dir + "/k.csv");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

}  // namespace

TEST(Trace, SurvivesSigkillAtAnyMoment) {
  const std::string dir = test::scratch_dir("trace_kill");
  for (int rows : {0, 1, 4, 11, 23}) kill_and_check(dir, rows);
}

TEST(Trace, BadContinuationInputIsRejectedBeforeAnyOutput) {
  const std::string dir = test::scratch_dir("trace_bad");
  const std::string scene = test::source_path("runs/scenes/bratu1d_fold.toml");
  struct Case {
    std::string overrides, expected;
  };
  const std::vector<Case> cases = {
      {"--set continuation.parameter=mu", "unknown parameter 'mu'; this problem has: lambda"},
      {"--set continuation.upper=-1", "lower = 0 must be below upper = -1"},
      {"--set continuation.stop_observable=nothing", "unknown observable 'nothing'"},
      {"--set continuation.initial_step=-0.1", "key 'continuation.initial_step' = -0.1 is out of range: must be > 0"},
      {"--set continuation.method=shooting", "is not one of: arclength, natural"},
      {"--set continuation.speed=1", "unknown key 'continuation.speed'"},
  };
  for (const Case& c : cases) {
    const auto r = test::run_keller("trace " + scene + " -o " + dir + "/x.h5 " + c.overrides);
    EXPECT_EQ(r.exit_code, 2) << c.overrides;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.overrides << ": " << r.err;
    EXPECT_FALSE(fs::exists(dir + "/x.h5")) << c.overrides;
  }
  // a scene without a continuation parameter cannot be traced
  const auto r =
      test::run_keller("trace " + test::source_path("runs/scenes/channel_stokes.toml") + " -o " + dir + "/y.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("a branch needs a parameter to continue in"), std::string::npos) << r.err;
}

// The collapsible-channel figure scripts run on a branch file of the coupled problem (coarse
// mesh), reading the stored interface profiles and the deformed mesh.
TEST(Trace, CollapsibleFiguresFromTheBranchFile) {
  const std::string dir = test::scratch_dir("trace_collapsible");
  const auto r = test::run_keller(
      "trace " + test::source_path("runs/scenes/collapsible_newtonian_thickness.toml") + " -o " + dir +
      "/c.h5 --set mesh.name=custom --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set mesh.nx_downstream=5"
      " --set mesh.ny_fluid=4 --set mesh.ny_solid=2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string cmd = test::python_module("keller.plot collapsible") + " " + dir + "/c.h5 -o " + dir + "/c > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  for (const char* f : {"branch", "interface", "path", "wall", "fields"})
    EXPECT_GT(fs::file_size(dir + "/c_" + f + ".png"), 10000u) << f;
  cmd = test::python_module("keller.plot interfaces") + " --newtonian " + dir + "/c.h5 " + dir + "/c.h5 -o " + dir +
        "/i.png > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_GT(fs::file_size(dir + "/i.png"), 10000u);
}

// python3 -m keller.mesh_convergence on the Bratu fold branch at 16, 32 and 64 intervals: u_mid is
// compared at the requested lambda = 1, 2, 3, then 3, 2 again past the fold (second visits kept
// apart). Central differences are second order, so halving h divides the change by 4.
TEST(Trace, MeshConvergenceScript) {
  const std::string dir = test::scratch_dir("trace_mesh_convergence");
  std::string files;
  for (int n : {16, 32, 64}) {
    const std::string out = dir + "/b" + std::to_string(n) + ".h5";
    const auto r = test::run_keller("trace " + test::source_path("runs/scenes/bratu1d_fold.toml") + " -o " + out +
                                    " --set bratu.intervals=" + std::to_string(n));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    files += " " + out;
  }
  const std::string cmd = test::python_module("keller.mesh_convergence") + files +
                          " --labels h16 h32 h64 --observables u_mid --csv " + dir + "/c.csv > " + dir + "/c.txt";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const auto [cols, rows] = read_csv(dir + "/c.csv");
  ASSERT_EQ(cols, (std::vector<std::string>{"lambda", "u_mid:h16->h32", "u_mid:h32->h64"}));
  ASSERT_EQ(rows.size(), 5u);  // lambda = 1, 2, 3 before the fold, 3, 2 after it
  const std::vector<double> lambdas = {1, 2, 3, 3, 2};
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i][0], lambdas[i]);
    EXPECT_NEAR(rows[i][1] / rows[i][2], 4.0, 0.1) << "lambda = " << rows[i][0];
  }
  std::ifstream txt(dir + "/c.txt");
  const std::string all((std::istreambuf_iterator<char>(txt)), std::istreambuf_iterator<char>());
  EXPECT_NE(all.find("mesh converged (h32 -> h64 within 0.01 in u_mid) up to lambda = 2"), std::string::npos) << all;
}

// Issue 30, item 12: a restart from the end of a finished branch does not sail past the stop
// that ended it (it traced 444 points of the 1D Bratu branch to a residual overflow, and 1052
// rows of the collapsible channel beyond min_m1 < 0): where the start lies on a stop (the stop
// observable's threshold, a bound) and the branch would go on beyond it, the branch ends at
// once, its one row the end (kind 6) at the start, exit 0. A restart from a row before the stop
// goes on to the same end as the original branch.
TEST(Trace, ARestartFromTheEndOfABranchEndsAtOnce) {
  const std::string dir = test::scratch_dir("trace_restart_end");
  const std::string coarse =
      " --set mesh.name=custom --set mesh.nx_upstream=5 --set mesh.nx_deformable=10 --set mesh.nx_downstream=5"
      " --set mesh.ny_fluid=4 --set mesh.ny_solid=2";
  struct Case {
    std::string name, scene, sets, reason;
  };
  const std::vector<Case> cases = {
      {"bratu_stop", "runs/scenes/bratu1d_fold.toml", "", "u_mid > stop_above"},
      {"bratu_upper", "runs/scenes/bratu1d_fold.toml", " --set continuation.upper=2.0", "upper bound"},
      {"channel_stop", "runs/scenes/collapsible_oldroyd_b_wi_low_gamma.toml", coarse, "min_m1 < stop_below"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string run = "trace " + test::source_path(c.scene) + c.sets + " --set output.xdmf=false -o ";
    auto r = test::run_keller(run + dir + "/" + c.name + ".h5");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const BranchTable b = read_branch_table(dir + "/" + c.name + ".h5");
    const long last = b.rows.rows() - 1;
    ASSERT_EQ(b.rows(last, b.column("kind")), 6);
    ASSERT_NE(b.status.find(c.reason), std::string::npos) << b.status;
    r = test::run_keller(run + dir + "/" + c.name + "_end.h5 --restart " + dir + "/" + c.name + ".h5:last");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("the branch is at its end where it starts"), std::string::npos) << r.out;
    const BranchTable e = read_branch_table(dir + "/" + c.name + "_end.h5");
    ASSERT_EQ(e.rows.rows(), 1) << e.status;
    EXPECT_EQ(e.rows(0, e.column("kind")), 6);
    EXPECT_NE(e.status.find(c.reason), std::string::npos) << e.status;
    for (const std::string& col : b.columns) {
      if (col != "row" && col != "kind" && col != "s" && col != "iterations" && col != "step" && col != "seconds" &&
          col != "saved_slot" && col.rfind("monitor:", 0) != 0) {
        EXPECT_EQ(e.rows(0, e.column(col)), b.rows(last, b.column(col))) << col;
      }
    }
    // from the row before the end: on to the same end
    r = test::run_keller(run + dir + "/" + c.name + "_on.h5 --restart " + dir + "/" + c.name +
                         ".h5:" + std::to_string(b.saved_rows.at(b.saved_rows.size() - 2)));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const BranchTable o = read_branch_table(dir + "/" + c.name + "_on.h5");
    const double end = b.rows(last, b.column(b.parameter)), reached = o.rows(o.rows.rows() - 1, o.column(b.parameter));
    EXPECT_NEAR(reached, end, 1e-8 * std::max(1.0, std::abs(end)));
    EXPECT_NE(o.status.find(c.reason), std::string::npos) << o.status;
  }
}
