// HDF5 wrapper: round trips of every kind of object it writes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/H5File.hpp"
#include "core/IoError.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

TEST(H5File, RoundTrips) {
  const std::string path = test::scratch_dir("h5") + "/a.h5";
  {
    H5File f(path, H5File::Mode::Create);
    f.write_string("/g/text", "hello [scene]\nx = 1");
    const double m[6] = {1, 2, 3, 4, 5, 6};
    f.write_matrix("/g/m", m, 2, 3);
    f.write_strings("/g/names", {"a", "bc"});
    f.set_attribute("/g/m", "basis", std::string("Q2"));
    f.set_attribute("/g/m", "value", 2.5);
    f.create_appendable("/t", 2);
    const double row[4] = {1, 2, 3, 4};
    f.append_rows("/t", row, 1);
    f.append_rows("/t", row + 2, 1);
    f.create_fixed_string("/status", 64);
    f.write_fixed_string("/status", "running");
    f.write_fixed_string("/status", "done");
  }
  H5File f(path, H5File::Mode::Read);
  EXPECT_EQ(f.read_string("/g/text"), "hello [scene]\nx = 1");
  long r = 0, c = 0;
  const auto m = f.read_matrix("/g/m", &r, &c);
  EXPECT_EQ(r, 2);
  EXPECT_EQ(c, 3);
  EXPECT_EQ(m, (std::vector<double>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(f.read_strings("/g/names"), (std::vector<std::string>{"a", "bc"}));
  EXPECT_EQ(f.read_string_attribute("/g/m", "basis"), "Q2");
  EXPECT_DOUBLE_EQ(f.read_double_attribute("/g/m", "value"), 2.5);
  EXPECT_EQ(f.num_rows("/t"), 2);
  EXPECT_EQ(f.read_matrix("/t", &r, &c), (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(f.read_string("/status"), "done");
  EXPECT_TRUE(f.exists("/g/m"));
  EXPECT_FALSE(f.exists("/nothing/here"));
  EXPECT_THROW(H5File("/nonexistent/dir/x.h5", H5File::Mode::Create), std::runtime_error);
}

// A create that fails never removes a file that was at the name before the call: not one that
// exists on disk, nor one open in this process (HDF5's refusal of a file it holds open carries
// no errno, which was taken for a failure of the call's own new file, and that file was removed).
TEST(H5File, ACreateThatFailsKeepsTheFileThatWasThere) {
  const std::string dir = test::scratch_dir("h5_create");
  const std::string open_here = dir + "/open.h5", closed = dir + "/closed.h5";
  {
    H5File held(open_here, H5File::Mode::Create);
    held.write_string("/text", "mine");
    held.flush();
    EXPECT_THROW(H5File(open_here, H5File::Mode::Create), IoError);
    EXPECT_TRUE(std::filesystem::exists(open_here));
  }
  EXPECT_EQ(H5File(open_here, H5File::Mode::Read).read_string("/text"), "mine");
  std::ofstream(closed) << "not HDF5\n";
  EXPECT_THROW(H5File(closed, H5File::Mode::Create), IoError);
  EXPECT_EQ(test::file_contents(closed), "not HDF5\n");
}
