// The rules every file keller writes obeys, tested as properties of core/RunFiles,
// core/PendingFile, core/HeldFile and core/OutputLock: an output is never an input or another
// output, whichever way its path is spelled or linked; a target that is not a regular file is
// refused; a file written under its temporary name reaches its target only complete, and a target
// is never left half-written; a temporary is never written through a link; what is published is
// the file written; one process at a time writes an output.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "continuation/output/RunFile.hpp"
#include "core/H5File.hpp"
#include "core/HeldFile.hpp"
#include "core/IoError.hpp"
#include "core/OutputLock.hpp"
#include "core/PendingFile.hpp"
#include "core/RunFiles.hpp"
#include "support/TestSupport.hpp"

using namespace keller;
namespace fs = std::filesystem;

namespace {

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
    EXPECT_EQ(test::file_contents(target), "old");  // untouched while the new file is written
  }                                                 // abandoned: the temporary file goes, the target stays
  EXPECT_EQ(test::file_contents(target), "old");
  EXPECT_FALSE(fs::exists(target + ".part"));
  {
    PendingFile p(target);
    write(p.path(), "new");
    p.commit();
    EXPECT_TRUE(p.done());
  }
  EXPECT_EQ(test::file_contents(target), "new");
  EXPECT_FALSE(fs::exists(target + ".part"));
  {
    PendingFile p(target);
    write(p.path(), "kept");
    p.keep();
  }
  EXPECT_EQ(test::file_contents(target + ".part"), "kept");  // the record of a run that did not finish
  EXPECT_EQ(test::file_contents(target), "new");
  // a target that turned into a link meanwhile is not replaced
  fs::remove(target);
  write(dir + "/elsewhere", "keep me");
  fs::create_symlink(dir + "/elsewhere", target);
  PendingFile p(target);
  write(p.path(), "x");
  EXPECT_THROW(p.commit(), std::runtime_error);
  EXPECT_TRUE(fs::is_symlink(target));
  EXPECT_EQ(test::file_contents(dir + "/elsewhere"), "keep me");
}

// Issue 30, item 5: a temporary is created exclusively, never through a name that exists; what an
// earlier run left is removed only where it is a regular file with no other name.
TEST(FileSafety, TemporariesAreCreatedExclusivelyNeverThroughALink) {
  const std::string dir = test::scratch_dir("exclusive");
  write(dir + "/victim", "keep me");
  fs::create_symlink(dir + "/victim", dir + "/symlink.part");
  fs::create_symlink(dir + "/nowhere", dir + "/dangling.part");
  fs::create_hard_link(dir + "/victim", dir + "/hard.part");
  write(dir + "/existing.part", "an earlier run's");
  for (const char* name : {"symlink.part", "dangling.part", "hard.part", "existing.part"}) {
    SCOPED_TRACE(name);
    EXPECT_THROW(::close(create_new_file(dir + "/" + name)), IoError);
    EXPECT_THROW(H5File(dir + "/" + name, H5File::Mode::Create), IoError);
  }
  EXPECT_FALSE(fs::exists(dir + "/nowhere"));
  for (const char* name : {"symlink.part", "dangling.part", "hard.part"}) {
    SCOPED_TRACE(name);
    try {
      clear_leftover(dir + "/" + name);
      ADD_FAILURE() << "cleared";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string(name) + "' is a"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_symlink(dir + "/" + name) || fs::exists(dir + "/" + name));
  }
  fs::create_directory(dir + "/folder.part");
  EXPECT_THROW(clear_leftover(dir + "/folder.part"), IoError);
  EXPECT_TRUE(fs::is_directory(dir + "/folder.part"));
  EXPECT_EQ(test::file_contents(dir + "/victim"), "keep me");
  clear_leftover(dir + "/existing.part");  // an earlier run's temporary: removed
  EXPECT_FALSE(fs::exists(dir + "/existing.part"));
  const int fd = create_new_file(dir + "/existing.part");
  write_all(fd, "new", dir + "/existing.part");
  ::close(fd);
  EXPECT_EQ(test::file_contents(dir + "/existing.part"), "new");
  // a PendingFile refuses the link at its temporary name as it starts
  EXPECT_THROW(PendingFile(dir + "/symlink"), IoError);
  EXPECT_EQ(test::file_contents(dir + "/victim"), "keep me");
}

// A run file that cannot take its name (a folder is there) is an I/O failure like any other
// (IoError, exit code 3), not a bad input; its temporary is removed and the folder left as it was.
TEST(FileSafety, ARunFileThatCannotTakeItsNameIsAnIoFailure) {
  const std::string dir = test::scratch_dir("run_file_rename");
  fs::create_directory(dir + "/run.h5");
  write(dir + "/run.h5/keep.txt", "mine");
  try {
    RunFile run(dir + "/run.h5", "/g", [](H5File& f) { f.create_group("/g"); });
    ADD_FAILURE() << "renamed over a folder";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/run.h5.part' to '" + dir + "/run.h5'"), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an IoError: " << e.what();
  }
  EXPECT_FALSE(fs::exists(dir + "/run.h5.part"));
  EXPECT_EQ(test::file_contents(dir + "/run.h5/keep.txt"), "mine");
}

// Item 6: a held file tells whether a name still refers to it, and what is published is the file
// written: a temporary replaced meanwhile is refused and left alone, and a held file that lost
// every name is copied out of its descriptor.
TEST(FileSafety, AHeldFileIsKnownByIdentityNotByName) {
  const std::string dir = test::scratch_dir("held");
  write(dir + "/a", "written by the run");
  write(dir + "/stranger", "another file");
  HeldFile held = HeldFile::open(dir + "/a");
  EXPECT_TRUE(held.at(dir + "/a"));
  EXPECT_FALSE(held.at(dir + "/stranger"));
  fs::create_symlink(dir + "/a", dir + "/link");
  EXPECT_FALSE(held.at(dir + "/link"));  // a link is not the file
  fs::rename(dir + "/a", dir + "/moved");
  EXPECT_TRUE(held.at(dir + "/moved"));
  EXPECT_TRUE(held.linked());
  fs::remove(dir + "/moved");
  fs::copy_file(dir + "/stranger", dir + "/a");  // a stranger at its old name
  EXPECT_FALSE(held.at(dir + "/a"));
  EXPECT_FALSE(held.linked());
  const HeldFile copy = held.copy_to(dir + "/saved");
  EXPECT_EQ(test::file_contents(dir + "/saved"), "written by the run");
  EXPECT_TRUE(copy.at(dir + "/saved"));
  EXPECT_THROW(held.copy_to(dir + "/saved"), IoError);  // never over a name that exists

  const std::string target = dir + "/out.csv";
  write(target, "old");
  {
    PendingFile p(target);
    p.write("new");
    fs::remove(p.path());
    write(p.path(), "swapped in");
    try {
      p.commit();
      ADD_FAILURE() << "committed";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find("is no longer the file this run wrote"), std::string::npos) << e.what();
    }
  }  // and not removed as if it were the run's
  EXPECT_EQ(test::file_contents(target), "old");
  EXPECT_EQ(test::file_contents(target + ".part"), "swapped in");
}

// Item 7: an output's lock refuses a second holder, naming the first's pid; it goes with its
// holder (a killed holder leaves at most an unlocked file, which the next run takes).
TEST(FileSafety, AnOutputLockRefusesASecondHolderNamingTheFirst) {
  const std::string dir = test::scratch_dir("lock");
  const std::string path = dir + "/c.h5.lock";
  EXPECT_EQ(OutputLock::path_for(dir + "/c.h5"), path);
  // another process tries the lock this one holds: its message, and 0 where it was refused
  auto other = [&]() {
    const pid_t pid = ::fork();
    if (pid == 0) {
      try {
        OutputLock second(path, "'c.h5'");
        ::_exit(1);
      } catch (const OutputLocked& e) {
        const std::string m = e.what();
        ::_exit(m.find("'c.h5' is in use by another keller process (pid " + std::to_string(::getppid()) + ", lock '" +
                       path + "')") != std::string::npos
                    ? 0
                    : 2);
      } catch (...) {
        ::_exit(3);
      }
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  {
    OutputLock first(path, "'c.h5'");
    EXPECT_TRUE(fs::exists(path));
    EXPECT_EQ(test::file_contents(path), std::to_string(::getpid()) + "\n");
    EXPECT_EQ(other(), 0);
  }
  EXPECT_FALSE(fs::exists(path));
  write(path, "12345\n");  // left by a killed run: not locked
  {
    OutputLock again(path, "'c.h5'");
    EXPECT_EQ(test::file_contents(path), std::to_string(::getpid()) + "\n");
  }
  write(dir + "/victim", "keep me");
  fs::create_symlink(dir + "/victim", path);
  EXPECT_THROW(OutputLock(path, "'c.h5'"), IoError);
  EXPECT_EQ(test::file_contents(dir + "/victim"), "keep me");
}
