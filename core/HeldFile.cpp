#include "core/HeldFile.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "core/IoError.hpp"
#include "core/PendingFile.hpp"

namespace keller {

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& path, int error) {
  throw IoError(fmt::format("{} '{}': {}", what, path, std::strerror(error)));
}

}  // namespace

HeldFile HeldFile::open(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) fail("cannot open", path, errno);
  HeldFile f = of_descriptor(fd, path);
  ::close(fd);
  return f;
}

HeldFile HeldFile::of_descriptor(int fd, const std::string& path) {
  HeldFile f;
  f.fd_ = ::fcntl(fd, F_DUPFD_CLOEXEC, 0);
  if (f.fd_ < 0) fail("cannot hold", path, errno);
  struct stat st {};
  if (::fstat(f.fd_, &st) != 0) fail("cannot inspect", path, errno);
  if (!S_ISREG(st.st_mode)) throw IoError(fmt::format("'{}' is not a regular file", path));
  f.device_ = st.st_dev;
  f.inode_ = st.st_ino;
  return f;
}

HeldFile::~HeldFile() {
  if (fd_ >= 0) ::close(fd_);
}

HeldFile::HeldFile(HeldFile&& o) noexcept : fd_(o.fd_), device_(o.device_), inode_(o.inode_) { o.fd_ = -1; }

HeldFile& HeldFile::operator=(HeldFile&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.fd_;
    device_ = o.device_;
    inode_ = o.inode_;
    o.fd_ = -1;
  }
  return *this;
}

bool HeldFile::at(const std::string& path) const {
  struct stat st {};
  return fd_ >= 0 && ::lstat(path.c_str(), &st) == 0 && st.st_dev == device_ && st.st_ino == inode_;
}

bool HeldFile::linked() const {
  struct stat st {};
  return fd_ >= 0 && ::fstat(fd_, &st) == 0 && st.st_nlink > 0;
}

HeldFile HeldFile::copy_to(const std::string& path) const {
  const int out = create_new_file(path);
  HeldFile copy;
  try {
    copy = of_descriptor(out, path);
    std::vector<char> buffer(std::size_t{1} << 20);
    for (off_t offset = 0;;) {
      const ssize_t n = ::pread(fd_, buffer.data(), buffer.size(), offset);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) fail("cannot read the file to copy to", path, errno);
      if (n == 0) break;
      write_all(out, std::string_view(buffer.data(), static_cast<size_t>(n)), path);
      offset += n;
    }
    if (::fsync(out) != 0) fail("cannot flush", path, errno);
  } catch (...) {
    ::close(out);
    throw;
  }
  if (::close(out) != 0) fail("cannot write", path, errno);
  return copy;
}

}  // namespace keller
