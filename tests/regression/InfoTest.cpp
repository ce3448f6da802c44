// What a new user sees: `keller info FILE.h5` (the kind of file, its scene, its stored rows with
// their kinds and labels, its provenance), located points named by labels where a row is taken
// (--restart FILE.h5:fold1 lands where --restart FILE.h5:ROW does; an unknown label is refused
// listing the file's labels), `keller --version`, the /provenance record of every output file,
// and a run printing only the keys of its scene that differ from their defaults.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

// a fixed renewal cost: the default measures it from timings, so two runs from one point (by label
// and by row, compared to every digit below) would otherwise take different chord paths under load
const std::string kBratu = " --set bratu.intervals=32 --set output.xdmf=false --set continuation.renewal_cost=25";

std::string bratu_scene() { return test::source_path("runs/scenes/bratu1d_fold.toml"); }

// The line of `text` that starts with `start` (after leading blanks); empty if none.
std::string line_starting(const std::string& text, const std::string& start) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    const size_t first = line.find_first_not_of(' ');
    if (first != std::string::npos && line.compare(first, start.size(), start) == 0) return line;
  }
  return {};
}

// The first stored row of the given kind (a number of PointKind), or -1.
int row_of_kind(const BranchTable& t, PointKind kind) {
  for (long i = 0; i < t.rows.rows(); ++i)
    if (static_cast<int>(t.rows(i, t.column("kind"))) == static_cast<int>(kind))
      return static_cast<int>(t.rows(i, t.column("row")));
  return -1;
}

}  // namespace

// The Bratu branch (32 intervals): start at lambda = 0, the stops 1, 2, 3, the fold near 3.51,
// the stops 3 and 2 again past it, the end at u_mid = 4. info lists every stored row with its kind
// and label, the labels counting each kind along the branch.
TEST(Info, ABranchListsItsStoredRowsKindsAndLabels) {
  const std::string dir = test::scratch_dir("info_branch");
  const std::string b = dir + "/b.h5";
  auto r = test::run_keller("trace " + bratu_scene() + kBratu + " -o " + b);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable t = read_branch_table(b);
  const int fold = row_of_kind(t, PointKind::Fold), end = row_of_kind(t, PointKind::End);
  ASSERT_GT(fold, 0);
  ASSERT_GT(end, fold);

  r = test::run_keller("info " + b);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(b + ": a branch in lambda (keller trace)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(fmt::format("{} rows, {} stored solutions", t.rows.rows(), t.saved_rows.size())),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("problem: bratu1d"), std::string::npos) << r.out;
  // the scene: what differs from the defaults (the override included), not every key
  EXPECT_NE(r.out.find("intervals = 32"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("stop_above = 4.0"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("# default"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("command: "), std::string::npos) << r.out;
  // every stored row, with its kind and label
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\n +0  start +start +0 "))) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(fmt::format("\\n +{}  fold1 +fold +3\\.51", fold)))) << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(fmt::format("\\n +{}  end +end ", end)))) << r.out;
  for (int k = 1; k <= 5; ++k)  // the stops 1, 2, 3, then 3 and 2 past the fold
    EXPECT_NE(r.out.find(fmt::format("  stop{} ", k)), std::string::npos) << k << "\n" << r.out;
  EXPECT_EQ(r.out.find("stop6"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(fmt::format("located points: start (row 0), stop1 (row ")), std::string::npos) << r.out;
  // every stored row is listed: one table line each
  int listed = 0;
  for (int row : t.saved_rows) listed += !line_starting(r.out, std::to_string(row) + "  ").empty();
  EXPECT_EQ(listed, static_cast<int>(t.saved_rows.size())) << r.out;

  // --scene: the whole resolved scene as stored
  r = test::run_keller("info " + b + " --scene");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  H5File f(b, H5File::Mode::Read);
  EXPECT_EQ(r.out, f.read_string("/scene"));
}

// A restart by label starts from the same row as by its number, and traces the same branch; a
// label the file does not have is refused (exit 2, nothing written) naming the labels it has.
TEST(Info, ARestartByLabelLandsOnTheRowItNames) {
  const std::string dir = test::scratch_dir("info_labels");
  const std::string b = dir + "/b.h5";
  auto r = test::run_keller("trace " + bratu_scene() + kBratu + " -o " + b);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable t = read_branch_table(b);
  const int fold = row_of_kind(t, PointKind::Fold);
  ASSERT_GT(fold, 0);

  const std::string restart = "trace " + bratu_scene() + kBratu + " --restart ";
  r = test::run_keller(restart + b + ":fold1 -o " + dir + "/by_label.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(fmt::format("restarting from row {} of {}", fold, b)), std::string::npos) << r.out;
  r = test::run_keller(restart + b + ":" + std::to_string(fold) + " -o " + dir + "/by_row.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable a = read_branch_table(dir + "/by_label.h5"), n = read_branch_table(dir + "/by_row.h5");
  ASSERT_EQ(a.rows.rows(), n.rows.rows());
  const int lambda = a.column("lambda"), u_mid = a.column("u_mid");
  for (long i = 0; i < a.rows.rows(); ++i) {
    EXPECT_EQ(a.rows(i, lambda), n.rows(i, lambda)) << "row " << i;
    EXPECT_EQ(a.rows(i, u_mid), n.rows(i, u_mid)) << "row " << i;
  }
  EXPECT_EQ(a.rows(0, lambda), t.rows(fold, t.column("lambda")));

  // labels count along the branch: stop4 is lambda = 3 past the fold, `end` and `start` stand alone
  r = test::run_keller("trace " + bratu_scene() + kBratu + " --restart " + b + ":stop4 -o " + dir + "/stop4.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_branch_table(dir + "/stop4.h5").rows(0, lambda), 3.0);
  EXPECT_GT(read_branch_table(dir + "/stop4.h5").rows(0, u_mid), t.rows(fold, t.column("u_mid")));

  r = test::run_keller(restart + b + ":hopf1 -o " + dir + "/no.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no located point labelled 'hopf1'; its labels: start (row 0), stop1 (row "), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(fmt::format("fold1 (row {})", fold)), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("end (row "), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/no.h5"));
  EXPECT_FALSE(fs::exists(dir + "/no.h5.part"));
  r = test::run_keller(restart + b + ":fold2 -o " + dir + "/no.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no located point labelled 'fold2'"), std::string::npos) << r.err;
  r = test::run_keller(restart + b + ":middle -o " + dir + "/no.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("'middle' is not a row number, 'last' or a located point's label"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/no.h5"));
}

// keller --version: the version of CMake's project(), the commit (40 hex digits: the tests are
// built from a git checkout where .git is there; "unknown" only outside git), the build type and
// the linear solver.
TEST(Info, VersionNamesVersionCommitBuildTypeAndLinearSolver) {
  const auto r = test::run_keller("--version");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("^keller [0-9]+\\.[0-9]+"))) << r.out;
  const bool in_git = fs::exists(test::source_path(".git"));
  EXPECT_TRUE(std::regex_search(r.out, std::regex(in_git ? "\\ncommit: [0-9a-f]{40}\\n" : "\\ncommit: unknown\\n")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\nbuild type: (Release|Debug|RelWithDebInfo|MinSizeRel|none)\\n")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\nlinear solver: (mumps|umfpack)"))) << r.out;
}

// keller --version names OpenBLAS's kernels, and the program runs with the CPU's own where OpenBLAS
// fell back to its generic Prescott ones (core/BlasThreads.hpp, use_native_blas_kernels): on a CPU
// with AVX2 and FMA never Prescott, unless KELLER_BLAS_KERNELS=keep, or OPENBLAS_CORETYPE chose.
TEST(Info, TheProgramRunsOpenBlasOnTheCpusOwnKernels) {
  if (std::getenv("OPENBLAS_CORETYPE") || std::getenv("KELLER_BLAS_KERNELS"))
    GTEST_SKIP() << "the kernels are chosen by this test's environment";
  const auto r = test::run_keller("--version");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::smatch m;
  if (!std::regex_search(r.out, m, std::regex("\\nBLAS: OpenBLAS, (\\S+) kernels"))) GTEST_SKIP() << "not OpenBLAS";
#if defined(__x86_64__)
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) GTEST_SKIP() << "a CPU without AVX2";
#else
  GTEST_SKIP() << "not x86-64";
#endif
  EXPECT_NE(m[1], "Prescott") << r.out;
  const auto chosen = test::run_keller("--version", "OPENBLAS_CORETYPE=Haswell");
  EXPECT_NE(chosen.out.find("\nBLAS: OpenBLAS, Haswell kernels"), std::string::npos) << chosen.out;
  const auto kept = test::run_keller("--version", "OPENBLAS_CORETYPE=Prescott");
  EXPECT_NE(kept.out.find("\nBLAS: OpenBLAS, Prescott kernels"), std::string::npos) << kept.out;
}

// Every output file records what made it (/provenance, as --version prints it, and the command
// line), and info names the kind of each file.
TEST(Info, EveryOutputFileRecordsItsProvenance) {
  const std::string dir = test::scratch_dir("info_provenance");
  const auto version = test::run_keller("--version");
  ASSERT_EQ(version.exit_code, 0);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(version.out, m,
                                std::regex("^keller (\\S+)\\ncommit: (\\S+)\\nbuild type: (\\S+)\\n"
                                           "linear solver: (\\S+)")))
      << version.out;
  const std::string v = m[1], commit = m[2], build = m[3], solver = m[4];

  struct Run {
    std::string command, file, says;
  };
  const std::string study = dir + "/s.toml";
  std::ofstream(study) << "[study]\nscene = \"" << bratu_scene()
                       << "\"\n\n[set]\n\"output.xdmf\" = false\n\n[grid]\n\"bratu.intervals\" = [16, 24]\n";
  const std::vector<Run> runs = {
      {"solve " + bratu_scene() + kBratu + " --set bratu.lambda=1.0 -o " + dir + "/s.h5", dir + "/s.h5",
       ": a steady state (keller solve)"},
      {"trace " + bratu_scene() + kBratu + " -o " + dir + "/t.h5", dir + "/t.h5", ": a branch in lambda"},
      {"evolve " + test::source_path("runs/scenes/brusselator1d_evolve.toml") +
           " --set evolve.t_end=1 --set output.xdmf=false -o " + dir + "/e.h5",
       dir + "/e.h5", ": a time series (keller evolve)"},
      {"study " + study + " --jobs 1 -o " + dir + "/study", dir + "/study/s.h5", ": a study's collected table"},
  };
  for (const Run& run : runs) {
    SCOPED_TRACE(run.command);
    auto r = test::run_keller(run.command);
    ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
    {
      H5File f(run.file, H5File::Mode::Read);
      ASSERT_TRUE(f.exists("/provenance"));
      EXPECT_EQ(f.read_string_attribute("/provenance", "keller_version"), v);
      EXPECT_EQ(f.read_string_attribute("/provenance", "commit"), commit);
      EXPECT_EQ(f.read_string_attribute("/provenance", "build_type"), build);
      EXPECT_EQ(f.read_string_attribute("/provenance", "linear_solver"), solver);
      const std::string line = f.read_string_attribute("/provenance", "command_line");
      EXPECT_NE(line.find(run.command.substr(0, run.command.find(' ')) + " "), std::string::npos) << line;
      EXPECT_NE(line.find(run.file.substr(0, run.file.rfind('/'))), std::string::npos) << line;
    }
    r = test::run_keller("info " + run.file);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find(run.file + run.says), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("made by: keller " + v + " (commit " + commit), std::string::npos) << r.out;
  }
  // a file keller did not write, and no file
  std::ofstream(dir + "/not.h5") << "not HDF5\n";
  auto r = test::run_keller("info " + dir + "/not.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(dir + "/not.h5"), std::string::npos) << r.err;
  r = test::run_keller("info " + dir + "/none.h5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

// A run prints the keys of its scene that differ from their defaults (the whole resolved scene is
// in its file), not all of them.
TEST(Info, ARunPrintsOnlyTheKeysThatDifferFromTheirDefaults) {
  const std::string dir = test::scratch_dir("info_printed_scene");
  const auto r = test::run_keller("trace " + bratu_scene() + kBratu + " -o " + dir + "/b.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string scene = r.out.substr(0, r.out.find("problem: "));
  EXPECT_NE(scene.find("# scene " + bratu_scene() + ": the keys that differ from their defaults"), std::string::npos)
      << scene;
  EXPECT_NE(scene.find("[bratu]\nintervals = 32\n"), std::string::npos) << scene;
  EXPECT_NE(scene.find("stop_above = 4.0"), std::string::npos) << scene;
  EXPECT_EQ(scene.find("# default"), std::string::npos) << scene;
  EXPECT_EQ(scene.find("[newton]"), std::string::npos) << scene;  // no key of it set
  EXPECT_NE(scene.find("keller info " + dir + "/b.h5 --scene"), std::string::npos) << scene;
  EXPECT_LT(std::count(scene.begin(), scene.end(), '\n'), 25) << scene;
}

// Durations in the summaries are printed for people: to the hundredth of a second, never with the
// 17 digits of a double (the stability line printed 0.14675487299999998 s).
TEST(Info, SummariesPrintDurationsToTheHundredth) {
  const std::string dir = test::scratch_dir("info_durations");
  const auto r = test::run_keller("trace " + test::source_path("runs/scenes/brusselator1d_hopf.toml") +
                                  " --set brusselator.intervals=16 --set output.xdmf=false -o " + dir + "/b.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\nstability: [0-9]+\\.[0-9]{2} s in [0-9]+ factorisations")))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\ntime [0-9]+\\.[0-9]{2} s: "))) << r.out;
  EXPECT_FALSE(std::regex_search(r.out, std::regex("[0-9]\\.[0-9]{12,} s\\b"))) << r.out;
}

// A curve starts from a located point by its label too (--from FILE:fold1), and info names the
// curve with both its parameters and lists its rows with both.
TEST(Info, ACurveFromALabelledFoldNamesBothParameters) {
  const std::string dir = test::scratch_dir("info_curve");
  const std::string scene = test::source_path("runs/scenes/bratu1d_shifted_fold_curve.toml") + kBratu;
  auto r = test::run_keller("trace " + scene + " -o " + dir + "/b.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = test::run_keller("trace " + scene + " --from " + dir + "/b.h5:fold1 --curve fold --free mu -o " + dir + "/c.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const BranchTable b = read_branch_table(dir + "/b.h5");
  EXPECT_NE(r.out.find(fmt::format("from the fold at row {} of", row_of_kind(b, PointKind::Fold))), std::string::npos)
      << r.out;
  r = test::run_keller("info " + dir + "/c.h5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(dir + "/c.h5: a fold curve in (mu, lambda) (keller trace --curve), from " + dir + "/b.h5:fold1"),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex("\\n +row +label +kind +mu +lambda +u_mid"))) << r.out;
}

// What a user reuses or cites keller under: the LICENSE is BSD-3-Clause, and CITATION.cff names
// the same license and the version keller --version prints (CMake's project(VERSION)).
TEST(Info, LicenseAndCitationAgreeWithTheBuild) {
  const std::string license = test::file_contents(test::source_path("LICENSE"));
  EXPECT_EQ(license.rfind("BSD 3-Clause License", 0), 0u);
  const std::string citation = test::file_contents(test::source_path("CITATION.cff"));
  EXPECT_NE(citation.find("cff-version: 1.2.0"), std::string::npos);
  EXPECT_NE(citation.find("\nlicense: BSD-3-Clause\n"), std::string::npos);
  const auto r = test::run_keller("--version");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("^keller ([0-9.]+)"))) << r.out;
  EXPECT_NE(citation.find("\nversion: \"" + m[1].str() + "\"\n"), std::string::npos) << m[1].str();
}
