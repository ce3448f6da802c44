#include "core/OutputLock.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "core/IoError.hpp"
#include "core/PendingFile.hpp"

namespace keller {

namespace {

bool same_inode(const struct stat& a, const struct stat& b) { return a.st_dev == b.st_dev && a.st_ino == b.st_ino; }

// The pid its holder wrote into the lock file (0 while it has not yet).
long holder_pid(int fd) {
  char buffer[32] = {};
  const ssize_t n = ::pread(fd, buffer, sizeof buffer - 1, 0);
  return n > 0 ? std::strtol(buffer, nullptr, 10) : 0;
}

}  // namespace

std::string OutputLock::path_for(const std::string& output) { return output + ".lock"; }

OutputLock::OutputLock(const std::string& lock_path, const std::string& what) : path_(lock_path) {
  // the holder removes the file as it releases it: a lock taken on a file that has lost its name
  // meanwhile is taken again on the file that has it now
  bool held_elsewhere = false;  // by a process that has not said its pid
  for (int attempt = 0; attempt < 20; ++attempt) {
    const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) {
      const int error = errno;
      if (error == ELOOP) clear_leftover(path_);  // says it is a link
      throw IoError(fmt::format("cannot make the lock file '{}' of {}: {}", path_, what, std::strerror(error)));
    }
    struct stat held {};
    if (::fstat(fd, &held) != 0 || !S_ISREG(held.st_mode) || held.st_nlink > 1) {
      ::close(fd);
      clear_leftover(path_);  // names what is there
      throw IoError(fmt::format("'{}' is not a lock file of keller; move it away", path_));
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      if (error != EWOULDBLOCK) {
        ::close(fd);
        throw IoError(fmt::format("cannot lock '{}' of {}: {}", path_, what, std::strerror(error)));
      }
      long pid = holder_pid(fd);  // written by the holder as it took the lock: a moment's wait
      for (int wait = 0; wait < 25 && pid <= 0; ++wait) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        pid = holder_pid(fd);
      }
      ::close(fd);
      held_elsewhere = pid <= 0;
      if (held_elsewhere) continue;  // released meanwhile, or not yet said: try again
      throw OutputLocked(fmt::format(
          "{} is in use by another keller process (pid {}, lock '{}'): one run at a time writes it; wait for that "
          "one to end (or stop it) and run this again",
          what, pid, path_));
    }
    struct stat named {};
    if (::stat(path_.c_str(), &named) != 0 || !same_inode(named, held)) {
      ::close(fd);
      continue;
    }
    fd_ = fd;
    const std::string pid = fmt::format("{}\n", ::getpid());
    if (::ftruncate(fd_, 0) == 0) {
      try {
        write_all(fd_, pid, path_);
      } catch (const IoError&) {  // the pid is for people; the lock itself holds
      }
    }
    return;
  }
  if (held_elsewhere)
    throw OutputLocked(
        fmt::format("{} is in use by another process (lock '{}'): one run at a time writes it", what, path_));
  throw IoError(fmt::format("cannot lock '{}' of {}: it keeps changing", path_, what));
}

OutputLock::~OutputLock() { release(); }

OutputLock::OutputLock(OutputLock&& o) noexcept : path_(std::move(o.path_)), fd_(o.fd_) { o.fd_ = -1; }

OutputLock& OutputLock::operator=(OutputLock&& o) noexcept {
  if (this != &o) {
    release();
    path_ = std::move(o.path_);
    fd_ = o.fd_;
    o.fd_ = -1;
  }
  return *this;
}

void OutputLock::release() {
  if (fd_ < 0) return;
  struct stat held {
  }, named{};
  if (::fstat(fd_, &held) == 0 && ::lstat(path_.c_str(), &named) == 0 && same_inode(held, named))
    ::unlink(path_.c_str());
  ::close(fd_);
  fd_ = -1;
}

}  // namespace keller
