// Nothing lost, whatever the user types and however a run ends: through the real driver, an
// output that is an input under another spelling or link is refused and the input is intact; a
// target that is not a regular file is refused; a failing run never replaces an existing
// result; a run signalled in any phase leaves every completed point readable and the same
// command continues it; starts from stored points check that the point belongs to the scene.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "runs/OutputFile.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

const std::string bratu1d = test::source_path("runs/scenes/bratu1d_fold.toml");
const std::string pitchfork = test::source_path("runs/scenes/pitchfork1d_trivial.toml");
// a short Bratu branch: 40 intervals, to the fold and back to u(1/2) = 4
const std::string quick = " --set bratu.intervals=40";

struct Refused {
  std::string args, expected;
};

// Runs each refused command and checks: exit code 2, the message, and that none of `watched`
// changed (contents compared byte for byte) or gained a temporary file.
void expect_refused(const std::vector<Refused>& cases, const std::vector<std::string>& watched) {
  std::vector<std::string> before;
  for (const auto& w : watched) before.push_back(test::file_contents(w));
  for (const Refused& c : cases) {
    SCOPED_TRACE(c.args);
    const auto r = test::run_keller(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
    for (size_t i = 0; i < watched.size(); ++i) {
      EXPECT_EQ(test::file_contents(watched[i]), before[i]) << watched[i] << " changed";
      EXPECT_FALSE(fs::exists(watched[i] + ".part")) << watched[i];
    }
  }
}

}  // namespace

// Items 2-5 of the issue and the rule behind them: by file identity, not spelling.
TEST(OutputSafety, NoOutputIsAnInputUnderAnyName) {
  const std::string dir = test::scratch_dir("safety_alias");
  auto r = test::run_keller("trace " + bratu1d + quick + " -o " + dir + "/b1.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string scene = dir + "/s.toml";
  fs::copy_file(bratu1d, scene);
  fs::create_symlink(dir + "/b1.h5", dir + "/link.h5");
  fs::create_hard_link(dir + "/b1.h5", dir + "/hard.h5");
  fs::create_directory(dir + "/sub");
  const std::string same = "is the same file as";
  expect_refused(
      {
          {"trace " + scene + " -o " + scene, same},
          {"solve " + scene + " -o " + dir + "/sub/../s.toml", same},
          {"trace " + scene + quick + " -o " + dir + "/out.xdmf", "are the same file"},
          {"export " + dir + "/b1.h5 --csv " + dir + "/b1.h5", same},
          {"export " + dir + "/b1.h5 --csv " + dir + "/./hard.h5", same},
          {"export " + dir + "/link.h5 --csv " + dir + "/b1.h5", same},
          {"trace " + scene + quick + " -o " + dir + "/b1.h5 --restart " + dir + "/./b1.h5:4", same},
          {"trace " + scene + quick + " -o " + dir + "/b1.h5 --restart " + dir + "/hard.h5:4", same},
          {"trace " + scene + quick + " -o " + dir + "/b1.h5 --restart " + dir + "/link.h5:4", same},
      },
      {scene, dir + "/b1.h5"});
  // the figure scripts follow the same rules
  const std::string before = test::file_contents(dir + "/b1.h5");
  const std::string script = test::python_module("keller.plot branch");
  EXPECT_NE(std::system((script + " " + dir + "/b1.h5 --y u_mid -o " + dir + "/hard.h5 2>/dev/null").c_str()), 0);
  EXPECT_NE(std::system((script + " " + dir + "/b1.h5 --y u_mid -o " + dir + "/link.h5 2>/dev/null").c_str()), 0);
  EXPECT_EQ(test::file_contents(dir + "/b1.h5"), before);
  EXPECT_EQ(std::system((script + " " + dir + "/b1.h5 --y u_mid -o " + dir + "/b1.png").c_str()), 0);
  EXPECT_TRUE(fs::exists(dir + "/b1.png"));
  EXPECT_FALSE(fs::exists(dir + "/b1.png.part"));
}

// Item 7: a link, a FIFO or a device is refused as a target and stays what it was; '-' writes
// the table to the standard output.
TEST(OutputSafety, TargetsThatAreNotRegularFilesAreRefused) {
  const std::string dir = test::scratch_dir("safety_kind");
  auto r = test::run_keller("trace " + bratu1d + quick + " -o " + dir + "/b1.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ofstream(dir + "/real.csv") << "mine\n";
  fs::create_symlink(dir + "/real.csv", dir + "/link.csv");
  ASSERT_EQ(::mkfifo((dir + "/fifo.csv").c_str(), 0600), 0);
  expect_refused({{"export " + dir + "/b1.h5 --csv " + dir + "/link.csv", "is a symbolic link"},
                  {"export " + dir + "/b1.h5 --csv " + dir + "/fifo.csv", "is a FIFO"},
                  {"export " + dir + "/b1.h5 --csv /dev/stdout", "is a symbolic link"},
                  {"solve " + bratu1d + " -o " + dir + "/link.csv", "is a symbolic link"}},
                 {dir + "/real.csv", dir + "/b1.h5"});
  EXPECT_TRUE(fs::is_symlink(dir + "/link.csv"));
  EXPECT_TRUE(fs::is_fifo(dir + "/fifo.csv"));
  r = test::run_keller("export " + dir + "/b1.h5 --csv -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("row,kind,s,lambda,", 0), 0u) << r.out.substr(0, 80);
  const BranchTable t = read_branch_table(dir + "/b1.h5");
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), t.rows.rows() + 1);
}

// Item 6: a run that fails after its first state leaves an existing result as it was; its own
// branch stays beside it under the temporary name. Without an existing file it takes the name.
TEST(OutputSafety, AFailingRunNeverReplacesAResult) {
  const std::string dir = test::scratch_dir("safety_fail");
  auto r = test::run_keller("trace " + bratu1d + quick + " -o " + dir + "/b1.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string good = test::file_contents(dir + "/b1.h5");
  // the renewal cost pinned: the two failing runs below must fail alike, to the residual in their
  // status, which a cost measured from the run's times would let differ
  const std::string failing = quick +
                              " --set continuation.min_step=5.0 --set continuation.initial_step=5.0"
                              " --set continuation.max_step=5.0 --set continuation.renewal_cost=25.0";
  r = test::run_keller("trace " + bratu1d + failing + " -o " + dir + "/b1.h5");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("is kept as it was"), std::string::npos) << r.out;
  EXPECT_EQ(test::file_contents(dir + "/b1.h5"), good);
  const BranchTable failed = read_branch_table(dir + "/b1.h5.part");
  EXPECT_NE(failed.status.find("step"), std::string::npos) << failed.status;
  r = test::run_keller("trace " + bratu1d + failing + " -o " + dir + "/new.h5");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(read_branch_table(dir + "/new.h5").status, failed.status);
  EXPECT_FALSE(fs::exists(dir + "/new.h5.part"));
  // a first state that does not converge writes nothing and keeps what is there
  r = test::run_keller("trace " + bratu1d + quick + " --set bratu.lambda=20 --set newton.max_iterations=3 -o " + dir +
                       "/b1.h5");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no output written"), std::string::npos) << r.err;
  EXPECT_EQ(test::file_contents(dir + "/b1.h5"), good);
}

// Items 8 and 9: a start from a stored point checks that the point belongs to this scene's
// problem (problem, physics, the fixed parameters) and that a switch is at a located branch
// point; --force lets a user through, with a warning.
TEST(OutputSafety, StoredStartsBelongToTheScene) {
  const std::string dir = test::scratch_dir("safety_start");
  auto r = test::run_keller("trace " + pitchfork + " --set continuation.upper=12 --set continuation.save_every=2 -o " +
                            dir + "/pf.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable pf = read_branch_table(dir + "/pf.h5");
  int branch_point = -1, regular = -1;
  for (int row : pf.saved_rows) {
    const int kind = static_cast<int>(pf.rows(row, pf.column("kind")));
    if (kind == 5 && branch_point < 0) branch_point = row;
    if (kind == 0 && row > 0 && regular < 0) regular = row;
  }
  ASSERT_GE(branch_point, 0);
  ASSERT_GE(regular, 0);
  // bratu1d and pitchfork1d with 64 intervals have the same 63 unknowns
  r = test::run_keller("trace " + bratu1d + " --set bratu.intervals=64 -o " + dir + "/x.h5 --restart " + dir +
                       "/pf.h5:" + std::to_string(regular));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("it was made by problem 'pitchfork1d', this scene is 'bratu1d'"), std::string::npos) << r.err;
  r = test::run_keller("trace " + pitchfork + " --set pitchfork.intervals=64 --set parameters.eps=0.5 -o " + dir +
                       "/x.h5 --restart " + dir + "/pf.h5:" + std::to_string(regular));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("it was traced at eps = 0, this scene sets eps = 0.5"), std::string::npos) << r.err;
  r = test::run_keller("trace " + pitchfork + " --set pitchfork.intervals=65 -o " + dir + "/x.h5 --restart " + dir +
                       "/pf.h5:" + std::to_string(regular));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("pitchfork.intervals = 64 in the file, 65 in this scene"), std::string::npos) << r.err;
  r = test::run_keller("trace " + pitchfork + " -o " + dir + "/sw.h5 --switch " + dir +
                       "/pf.h5:" + std::to_string(regular));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("is not a located branch point (located branch points with a stored solution: " +
                       std::to_string(branch_point) + ")"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(dir + "/sw.h5"));
  r = test::run_keller("trace " + pitchfork + " --set continuation.upper=20 -o " + dir + "/sw.h5 --switch " + dir +
                       "/pf.h5:" + std::to_string(branch_point));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = test::run_keller("trace " + pitchfork + " --set continuation.upper=12 --set continuation.max_steps=3 -o " + dir +
                       "/forced.h5 --force --switch " + dir + "/pf.h5:" + std::to_string(regular));
  EXPECT_NE(r.err.find("keller: warning:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(--force)"), std::string::npos) << r.err;
}

// A key added to keller after a file was written is not in the file's records: at its default it
// keeps the physics the file was made with, so a start from the file is not refused for it (at
// another value it is), and neither is the continuation of an unfinished run. A key the file has
// and the scene does not, or a value that differs, still is.
TEST(OutputSafety, AKeyAddedSinceAFileWasWrittenAtItsDefaultIsNotADifference) {
  const std::string defaults = "a.x = 1\nb.y = \"auto\"\n";
  EXPECT_TRUE(records_agree("a.x = 1\n", "a.x = 1\nb.y = \"auto\"\n", defaults));
  EXPECT_EQ(record_difference("a.x = 1\n", "a.x = 1\nb.y = \"auto\"\n", defaults), "");
  EXPECT_FALSE(records_agree("a.x = 1\n", "a.x = 1\nb.y = \"mumps\"\n", defaults));
  EXPECT_EQ(record_difference("a.x = 1\n", "a.x = 1\nb.y = \"mumps\"\n", defaults),
            "b.y = \"mumps\" in this scene, not in the file");
  EXPECT_FALSE(records_agree("a.x = 2\n", "a.x = 1\n", defaults));
  EXPECT_FALSE(records_agree("a.x = 1\nc.z = 3\n", "a.x = 1\n", defaults));  // a key removed since
  EXPECT_FALSE(records_agree("a.x = 1\n", "a.x = 1\nd.w = 5\n", defaults));  // not a key with a default

  // through the driver: the file's record without one of its keys, as keller wrote it before the key
  const std::string dir = test::scratch_dir("safety_new_key");
  const std::string brusselator = test::source_path("runs/scenes/brusselator1d_hopf.toml") +
                                  " --set brusselator.intervals=8 --set stability.enabled=false";
  auto r = test::run_keller("trace " + brusselator + " --set continuation.max_steps=3 -o " + dir + "/bz.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string key = "brusselator.length";  // 1 by default
  {
    H5File f(dir + "/bz.h5", H5File::Mode::ReadWrite);
    std::string physics = f.read_string("/problem/physics");
    const auto at = physics.find(key + " = ");
    ASSERT_NE(at, std::string::npos) << physics;
    physics.erase(at, physics.find('\n', at) + 1 - at);
    ASSERT_FALSE(physics.empty());
    f.remove("/problem/physics");
    f.write_string("/problem/physics", physics);
  }
  r = test::run_keller("trace " + brusselator + " --set continuation.max_steps=2 -o " + dir + "/a.h5 --restart " + dir +
                       "/bz.h5:last");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("physics differs"), std::string::npos) << r.err;
  r = test::run_keller("trace " + brusselator + " --set continuation.max_steps=2 --set " + key + "=0.5 -o " + dir +
                       "/b.h5 --restart " + dir + "/bz.h5:last");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(key + " = 0.5 in this scene, not in the file"), std::string::npos) << r.err;
}

// Items 10-15: what the user types costs a message naming the key, never a result or a silent
// change, and every usage error exits with 2.
TEST(OutputSafety, BadValuesAndUsageGetClearMessagesAndCode2) {
  const std::string dir = test::scratch_dir("safety_usage");
  const std::string collapsible = test::source_path("runs/scenes/collapsible_oldroyd_b.toml");
  const std::vector<Refused> cases = {
      {"trace " + bratu1d + " --set \"$(printf 'continuation.max_steps=3\\n[problem]')\" -o " + dir + "/o.h5",
       "a value cannot contain a line break"},
      {"solve " + collapsible + " --set parameters.Wi=inf -o " + dir + "/o.h5",
       "key 'parameters.Wi' = inf is not a finite number (must be > 0)"},
      {"solve " + bratu1d + " --set bratu.intervals=2147483658 -o " + dir + "/o.h5",
       "key 'bratu.intervals' = 2147483658 is out of range: must be in [2, 10000000]"},
      {"solve " + bratu1d + " --set bratu.intervals=2147483647 -o " + dir + "/o.h5",
       "key 'bratu.intervals' = 2147483647 is out of range"},
      {"solve " + collapsible + " --set parameters.t=20.0 -o " + dir + "/o.h5",
       "(--set): key 'parameters.t' = 20 is out of range: must be in [0.001, 10]"},
      {"trace " + bratu1d + " --frobnicate", "keller: error:"},
      {"trace " + bratu1d + " --switch-direction 3", "keller: error:"},
      {"trace", "trace needs a scene file"},
      {"frobnicate", "keller: error:"},
      {"export", "keller: error:"},
      {"trace " + bratu1d + " -o " + dir + "/o.h5 --force",
       "--force applies to a start from --restart, --switch or --from"},
  };
  for (const Refused& c : cases) {
    SCOPED_TRACE(c.args);
    const auto r = test::run_keller(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir + "/o.h5"));
  }
  auto r = test::run_keller("solve --help-scene");
  EXPECT_NE(r.out.find("  t = 0.4\n      wall thickness t (units of W); a number, in [0.001, 10]"), std::string::npos);
  for (const std::string help : {"--help", "trace --help", "export --help"}) {
    r = test::run_keller(help);
    EXPECT_EQ(r.exit_code, 0) << help;
    EXPECT_NE(r.out.find("Exit codes: 0 done; 1 numerical failure"), std::string::npos) << help;
    EXPECT_NE(r.out.find("130 interrupted"), std::string::npos) << help;
  }
  // item 14: solve takes a branch scene's first state, saying it leaves the trace sections aside
  r = test::run_keller("solve " + bratu1d + " -o " + dir + "/first.h5");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("[continuation] is for keller trace and left aside"), std::string::npos) << r.out;
}

namespace {

struct Phase {
  std::string at;  // KELLER_SIGNAL_AT
  bool finished;   // the branch had ended when the signal came
  bool written;    // and its fields too: SIGINT or SIGTERM no longer stop anything
};

// The located fold and the end of a Bratu branch: what any correct run of the scene finds,
// whichever way its steps went.
std::pair<double, double> fold_and_end(const BranchTable& t) {
  double fold = NAN;
  const int kind = t.column("kind"), lambda = t.column("lambda");
  for (long i = 0; i < t.rows.rows(); ++i)
    if (static_cast<int>(t.rows(i, kind)) == 4) fold = t.rows(i, lambda);
  return {fold, t.rows(t.rows.rows() - 1, lambda)};
}

}  // namespace

// Item 1 and the rule behind it: the run is signalled (SIGINT, SIGTERM, SIGKILL) in each phase,
// from the middle of the branch to the renaming of the finished file. Whatever the phase, an
// existing result is either as it was or the complete new branch, every completed point is in a
// readable file, and the same command run again ends with the whole branch (continuing an
// unfinished one from its last stored solution).
TEST(OutputSafety, ARunSignalledInAnyPhaseLosesNothingAndTheSameCommandFinishesIt) {
  const std::string dir = test::scratch_dir("safety_signals");
  const std::string scene = test::source_path("runs/scenes/bratu2d_fold.toml");
  const std::string args = " --set bratu.intervals=8 --set continuation.save_every=2 --set continuation.max_step=0.2";
  auto r = test::run_keller("trace " + scene + args + " -o " + dir + "/reference.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable reference = read_branch_table(dir + "/reference.h5");
  const auto [fold, end] = fold_and_end(reference);
  ASSERT_TRUE(std::isfinite(fold));
  ASSERT_GT(reference.rows.rows(), 8);
  r = test::run_keller("trace " + scene + args + " --set continuation.stop_above=1.0 -o " + dir + "/earlier.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string earlier = test::file_contents(dir + "/earlier.h5");
  const std::vector<Phase> phases = {{"point:6", false, false},
                                     {"traced", true, false},
                                     {"fields:2", true, false},
                                     {"fields-written", true, true},
                                     {"published", true, true}};
  for (const Phase& phase : phases)
    for (const std::string sig : {"INT", "TERM", "KILL"}) {
      SCOPED_TRACE(phase.at + " " + sig);
      const std::string out = dir + "/b.h5", work = out + ".part";
      for (const std::string& f : {out, work, out + ".fields.part"}) fs::remove(f);
      std::ofstream(out, std::ios::binary) << earlier;
      const std::string command = "trace " + scene + args + " -o " + out;
      r = test::run_keller(command, "KELLER_SIGNAL_AT=" + phase.at + " KELLER_SIGNAL=" + sig);
      if (sig == "KILL") {
        EXPECT_EQ(r.exit_code, -1) << "not killed: " << r.out;
      } else {
        EXPECT_EQ(r.exit_code, phase.written ? 0 : 130) << r.err;
      }
      // the target: the earlier result, or the whole new branch, never anything else
      const bool replaced = test::file_contents(out) != earlier;
      if (replaced) {
        const BranchTable t = read_branch_table(out);
        EXPECT_EQ(t.rows.rows(), reference.rows.rows());
        EXPECT_NE(t.status, "running");
      }
      // a finished branch takes the name unless it was killed before the renaming
      EXPECT_EQ(replaced, phase.at == "published" || (phase.finished && sig != "KILL")) << "replaced: " << replaced;
      // every completed point is readable, under one name or the other
      if (!replaced) {
        ASSERT_TRUE(fs::exists(work));
        const BranchTable t = read_branch_table(work);
        EXPECT_GE(t.rows.rows(), phase.finished ? reference.rows.rows() : 6);
        EXPECT_TRUE(t.rows.allFinite());
        const auto e = test::run_keller("export " + work + " --csv " + dir + "/w.csv");
        EXPECT_EQ(e.exit_code, 0) << e.err;
      }
      // the same command again: the whole branch under its name, nothing left beside it
      BranchSeed seed;
      const bool unfinished = fs::exists(work) && !phase.finished;
      if (unfinished) seed = read_branch_seed(work);
      r = test::run_keller(command);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      if (unfinished) {
        EXPECT_NE(r.out.find("continuing the unfinished branch"), std::string::npos) << r.out;
      }
      const BranchTable t = read_branch_table(out);
      EXPECT_EQ(t.status, reference.status);
      const auto [f, e] = fold_and_end(t);
      EXPECT_NEAR(f, fold, 1e-8);
      EXPECT_NEAR(e, end, 1e-8);
      for (long i = 0; i < t.rows.rows(); ++i) EXPECT_EQ(t.rows(i, t.column("row")), static_cast<double>(i));
      if (unfinished) {  // the rows it continued from are the interrupted run's own
        EXPECT_EQ((t.rows.topRows(seed.row + 1) - seed.table).cwiseAbs().maxCoeff(), 0.0);
      }
      EXPECT_FALSE(fs::exists(work));
      EXPECT_FALSE(fs::exists(out + ".fields.part"));
      EXPECT_TRUE(fs::exists(dir + "/b.xdmf"));
    }
}

// An unfinished branch of another command is never continued nor overwritten silently.
TEST(OutputSafety, AnUnfinishedBranchOfAnotherRunIsKept) {
  const std::string dir = test::scratch_dir("safety_other");
  const std::string scene = test::source_path("runs/scenes/bratu2d_fold.toml");
  const std::string out = dir + "/b.h5";
  auto r = test::run_keller("trace " + scene + " --set bratu.intervals=8 -o " + out, "KELLER_SIGNAL_AT=point:3");
  ASSERT_EQ(r.exit_code, -1);
  const std::string unfinished = test::file_contents(out + ".part");
  r = test::run_keller("trace " + scene + " --set bratu.intervals=10 -o " + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("holds the unfinished branch"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bratu.intervals = 8 in the file, 10 in this scene"), std::string::npos) << r.err;
  EXPECT_EQ(test::file_contents(out + ".part"), unfinished);
  r = test::run_keller("trace " + scene + " --set bratu.intervals=10 -o " + out + " --fresh");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out + ".part"));
}

// Issue 30, item 12: an empty -o is an error of every command (not the default name); the XDMF
// file escapes the name of the HDF5 file it refers to; `export --xdmf` of a branch without a mesh
// says there are no fields instead of claiming it wrote them; evolve names the key at fault.
TEST(OutputSafety, EmptyNamesEscapedNamesAndNoFields) {
  const std::string dir = test::scratch_dir("safety_small");
  auto r = test::run_keller("trace " + bratu1d + quick + " -o " + dir + "/b1.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string b1 = test::file_contents(dir + "/b1.h5");
  std::ofstream(dir + "/s.toml") << "[study]\nscene = \"" << bratu1d << "\"\n[grid]\n\"bratu.intervals\" = [16]\n";
  const std::string evolve = test::source_path("runs/scenes/brusselator1d_evolve.toml");
  const std::vector<std::string> defaults = {"bratu1d_fold.h5", "brusselator1d_evolve.h5", "s"};  // here
  for (const std::string& made : defaults) fs::remove_all(made);
  for (const std::string& c :
       {"solve " + bratu1d + " -o ''", "trace " + bratu1d + " -o ''", "evolve " + evolve + " -o ''",
        "study " + dir + "/s.toml -o ''", "export " + dir + "/b1.h5 --csv ''"}) {
    SCOPED_TRACE(c);
    r = test::run_keller(c);
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("an empty path"), std::string::npos) << r.err;
  }
  for (const std::string& made : defaults) EXPECT_FALSE(fs::exists(made)) << made;

  r = test::run_keller("trace " + test::source_path("runs/scenes/bratu2d_fold.toml") +
                       " --set bratu.intervals=4 --set continuation.max_steps=3 -o '" + dir + "/a&<>\"'\\''.h5'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string xdmf = test::file_contents(dir + "/a&<>\"'.xdmf");
  EXPECT_NE(xdmf.find(">a&amp;&lt;&gt;&quot;&apos;.h5:/"), std::string::npos) << xdmf.substr(0, 600);
  EXPECT_EQ(xdmf.find("a&<"), std::string::npos);

  r = test::run_keller("export " + dir + "/b1.h5 --xdmf");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("'" + dir + "/b1.h5' has no mesh (problem 'bratu1d'): there are no fields to write"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(test::file_contents(dir + "/b1.h5") == b1) << "changed";
  for (const char* made : {"/b1.xdmf", "/b1-fields.h5"}) EXPECT_FALSE(fs::exists(dir + made)) << made;

  r = test::run_keller("evolve " + evolve + " --set evolve.max_step=1e-300 -o " + dir + "/e.h5");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("key 'evolve.max_step'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1e-300 is below"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("evolve.initial_step"), std::string::npos) << r.err;
}
