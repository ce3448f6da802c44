// The rules every file keller writes obeys, tested as properties of core/RunFiles and
// core/PendingFile: an output is never an input or another output, whichever way its path is
// spelled or linked; a target that is not a regular file is refused; a file written under its
// temporary name reaches its target only complete, and a target is never left half-written.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/PendingFile.hpp"
#include "core/RunFiles.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

std::string contents(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// Every way of naming `file` (a regular file in `dir`, whose path is `dir/name`) that the
// rules must see through.
std::vector<std::string> aliases_of(const std::string& dir, const std::string& name) {
  fs::create_directories(dir + "/sub");
  fs::create_symlink(dir + "/" + name, dir + "/link_to_" + name);
  fs::create_hard_link(dir + "/" + name, dir + "/hard_" + name);
  fs::create_directory_symlink(dir, dir + "/dirlink");
  const std::string rel = fs::relative(dir + "/" + name).string();
  return {dir + "/" + name,
          dir + "/./" + name,
          dir + "/sub/../" + name,
          dir + "//" + name,
          dir + "/link_to_" + name,
          dir + "/hard_" + name,
          dir + "/dirlink/" + name,
          rel,
          "./" + rel};
}

}  // namespace

TEST(FileSafety, SameFileSeesThroughEverySpellingAndLink) {
  const std::string dir = test::scratch_dir("same_file");
  write(dir + "/a.h5", "a");
  write(dir + "/b.h5", "b");
  for (const std::string& alias : aliases_of(dir, "a.h5")) {
    EXPECT_TRUE(same_file(dir + "/a.h5", alias)) << alias;
    EXPECT_FALSE(same_file(dir + "/b.h5", alias)) << alias;
  }
  // paths that do not exist yet are the same file when they resolve to the same place
  EXPECT_TRUE(same_file(dir + "/new.h5", dir + "/sub/../new.h5"));
  EXPECT_TRUE(same_file(dir + "/new.h5", dir + "/dirlink/new.h5"));
  EXPECT_FALSE(same_file(dir + "/new.h5", dir + "/new.h5.part"));
  EXPECT_FALSE(same_file(dir + "/new.h5", dir + "/a.h5"));
}

TEST(FileSafety, NoOutputAliasesAnInputOrAnotherOutput) {
  const std::string dir = test::scratch_dir("run_files_alias");
  write(dir + "/scene.toml", "x");
  for (const std::string& alias : aliases_of(dir, "scene.toml")) {
    RunFiles files;
    files.input("scene file", dir + "/scene.toml");
    files.output("branch file", alias);
    try {
      files.check();
      ADD_FAILURE() << "accepted " << alias;
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("is the same file as the scene file"), std::string::npos) << m;
    }
    // and two outputs of one run, one of them not created yet
    RunFiles two;
    two.output("branch file", dir + "/out.h5");
    two.output("XDMF file", dir + "/sub/../out.h5");
    EXPECT_THROW(two.check(), std::invalid_argument);
  }
  RunFiles fine;
  fine.input("scene file", dir + "/scene.toml");
  fine.output("branch file", dir + "/out.h5");
  fine.output("XDMF file", dir + "/out.xdmf");
  EXPECT_NO_THROW(fine.check());
}

TEST(FileSafety, TargetsThatAreNotRegularFilesAreRefused) {
  const std::string dir = test::scratch_dir("run_files_kind");
  write(dir + "/real.csv", "x");
  fs::create_symlink(dir + "/real.csv", dir + "/link.csv");
  fs::create_symlink(dir + "/nowhere.csv", dir + "/dangling.csv");
  ASSERT_EQ(::mkfifo((dir + "/fifo.csv").c_str(), 0600), 0);
  fs::create_directory(dir + "/folder.csv");
  const std::vector<std::pair<std::string, std::string>> cases = {{dir + "/link.csv", "a symbolic link"},
                                                                  {dir + "/dangling.csv", "a symbolic link"},
                                                                  {dir + "/fifo.csv", "a FIFO"},
                                                                  {dir + "/folder.csv", "a directory"},
                                                                  {"/dev/null", "a device"},
                                                                  {"/dev/stdout", "a symbolic link"},
                                                                  {dir + "/missing/x.csv", "does not exist"}};
  for (const auto& [path, what] : cases) {
    RunFiles files;
    files.output("--csv file", path);
    try {
      files.check();
      ADD_FAILURE() << "accepted " << path;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  }
  RunFiles regular;
  regular.output("--csv file", dir + "/real.csv");
  regular.output("--csv file", dir + "/absent.csv");
  EXPECT_NO_THROW(regular.check());
}

TEST(FileSafety, APendingFileReachesItsTargetOnlyComplete) {
  const std::string dir = test::scratch_dir("pending");
  const std::string target = dir + "/out.csv";
  write(target, "old");
  {
    PendingFile p(target);
    EXPECT_EQ(p.path(), target + ".part");
    write(p.path(), "new, half");
    EXPECT_EQ(contents(target), "old");  // untouched while the new file is written
  }                                      // abandoned: the temporary file goes, the target stays
  EXPECT_EQ(contents(target), "old");
  EXPECT_FALSE(fs::exists(target + ".part"));
  {
    PendingFile p(target);
    write(p.path(), "new");
    p.commit();
    EXPECT_TRUE(p.done());
  }
  EXPECT_EQ(contents(target), "new");
  EXPECT_FALSE(fs::exists(target + ".part"));
  {
    PendingFile p(target);
    write(p.path(), "kept");
    p.keep();
  }
  EXPECT_EQ(contents(target + ".part"), "kept");  // the record of a run that did not finish
  EXPECT_EQ(contents(target), "new");
  // a target that turned into a link meanwhile is not replaced
  fs::remove(target);
  write(dir + "/elsewhere", "keep me");
  fs::create_symlink(dir + "/elsewhere", target);
  PendingFile p(target);
  write(p.path(), "x");
  EXPECT_THROW(p.commit(), std::runtime_error);
  EXPECT_TRUE(fs::is_symlink(target));
  EXPECT_EQ(contents(dir + "/elsewhere"), "keep me");
}
