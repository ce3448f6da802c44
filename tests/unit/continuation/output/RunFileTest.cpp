// The file of a run written row by row (continuation/output/RunFile), which branch files and time
// series are laid out in: it takes its name only once laid out, says "running" with exit code -1
// until the run ends, and leaves nothing where its layout fails. (A name it cannot take:
// FileSafetyTest.)
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "continuation/output/RunFile.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

double exit_code(const std::string& path, const std::string& group) {
  H5File f(path, H5File::Mode::Read);
  long rows = 0, cols = 0;
  const std::vector<double> code = f.read_matrix(group + "/exit_code", &rows, &cols);
  return rows == 1 && cols == 1 ? code.front() : NAN;
}

std::string status(const std::string& path, const std::string& group) {
  H5File f(path, H5File::Mode::Read);
  return f.read_string(group + "/status");
}

}  // namespace

// Laid out, it has its final name (no temporary left), "running" and -1, and its rows are on disk
// for a reader while it is open; ended() then finish() store why and the code, and close it.
TEST(RunFile, SaysRunningUntilItsRunEndsThenWhyAndTheCode) {
  const std::string path = test::scratch_dir("run_file_end") + "/run.h5";
  RunFile run(path, "/g", [](H5File& f) {
    f.create_group("/g");
    f.create_appendable("/g/table", 2);
  });
  EXPECT_TRUE(run.is_open());
  EXPECT_TRUE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".part"));
  EXPECT_TRUE(run.written().at(path));
  const double row[2] = {1.0, 2.5};
  run.h5().append_rows("/g/table", row, 1);
  run.h5().flush();
  EXPECT_EQ(status(path, "/g"), "running");
  EXPECT_EQ(exit_code(path, "/g"), -1.0);
  {
    H5File reader(path, H5File::Mode::Read);
    EXPECT_EQ(reader.num_rows("/g/table"), 1);
  }
  run.ended("reached the upper bound");
  EXPECT_EQ(status(path, "/g"), "running");  // stored by finish, with the code, in one flush
  run.finish(0);
  EXPECT_FALSE(run.is_open());
  EXPECT_EQ(status(path, "/g"), "reached the upper bound");
  EXPECT_EQ(exit_code(path, "/g"), 0.0);
}

// A run whose file does not take its name (its output is published elsewhere) keeps exit code -1;
// a run that never ended says "running".
TEST(RunFile, AFileThatTakesNoNameKeepsCodeMinusOne) {
  const std::string dir = test::scratch_dir("run_file_unnamed");
  {
    RunFile run(dir + "/a.h5", "/g", [](H5File& f) { f.create_group("/g"); });
    run.ended("step budget");
    run.finish(std::nullopt);
  }
  EXPECT_EQ(status(dir + "/a.h5", "/g"), "step budget");
  EXPECT_EQ(exit_code(dir + "/a.h5", "/g"), -1.0);
  {
    RunFile run(dir + "/b.h5", "/g", [](H5File& f) { f.create_group("/g"); });
  }
  EXPECT_EQ(status(dir + "/b.h5", "/g"), "running");
  EXPECT_EQ(exit_code(dir + "/b.h5", "/g"), -1.0);
}

// A layout that fails (a seed that does not fit) leaves neither the file nor its temporary, and
// its error reaches the caller unchanged; what an earlier run left at the temporary name is cleared.
TEST(RunFile, ALayoutThatFailsLeavesNothing) {
  const std::string dir = test::scratch_dir("run_file_layout");
  {
    RunFile leftover(dir + "/run.h5.part.h5", "/g", [](H5File& f) { f.create_group("/g"); });
  }
  fs::rename(dir + "/run.h5.part.h5", dir + "/run.h5.part");
  try {
    RunFile run(dir + "/run.h5", "/g", [](H5File& f) {
      f.create_group("/g");
      throw std::runtime_error("the unfinished run has other columns");
    });
    ADD_FAILURE() << "a failed layout was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "the unfinished run has other columns");
  }
  EXPECT_FALSE(fs::exists(dir + "/run.h5"));
  EXPECT_FALSE(fs::exists(dir + "/run.h5.part"));
}
