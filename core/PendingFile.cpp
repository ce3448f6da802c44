#include "core/PendingFile.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/IoError.hpp"

namespace keller {

namespace fs = std::filesystem;

void sync_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError(fmt::format("cannot open '{}' to flush it: {}", path, std::strerror(errno)));
  const int rc = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (rc != 0) throw IoError(fmt::format("cannot flush '{}' to disk: {}", path, std::strerror(error)));
}

void clear_leftover(const std::string& temporary) {
  struct stat st {};
  if (::lstat(temporary.c_str(), &st) != 0) return;
  std::string what;
  if (S_ISLNK(st.st_mode))
    what = "a symbolic link";
  else if (S_ISDIR(st.st_mode))
    what = "a directory";
  else if (!S_ISREG(st.st_mode))
    what = "not a regular file";
  else if (st.st_nlink > 1)
    what = "a file with other names (a hard link)";
  if (!what.empty())
    throw IoError(
        fmt::format("'{}' is {}: keller creates its temporary files under this name itself and never writes through "
                    "another file; move it away",
                    temporary, what));
  if (::unlink(temporary.c_str()) != 0 && errno != ENOENT)
    throw IoError(fmt::format("cannot remove the leftover '{}': {}", temporary, std::strerror(errno)));
}

int create_new_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int error = errno;
    if (error == EEXIST)
      throw IoError(fmt::format("cannot create '{}': the name was taken by another file meanwhile", path));
    throw IoError(fmt::format("cannot create '{}': {}", path, std::strerror(error)));
  }
  return fd;
}

void write_all(int fd, std::string_view data, const std::string& path) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd, data.data(), data.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw IoError(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
    data.remove_prefix(static_cast<size_t>(n));
  }
}

PendingFile::PendingFile(std::string target) : target_(std::move(target)), path_(temporary_for(target_)) {
  clear_leftover(path_);
}

std::string PendingFile::temporary_for(const std::string& target) { return target + ".part"; }

PendingFile::~PendingFile() {
  if (done_ || (file_.held() && !file_.at(path_))) return;
  std::error_code ec;
  fs::remove(path_, ec);
}

void PendingFile::write(std::string_view text) {
  const int fd = create_new_file(path_);
  try {
    file_ = HeldFile::of_descriptor(fd, path_);
    write_all(fd, text, path_);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0) throw IoError(fmt::format("cannot write '{}': {}", path_, std::strerror(errno)));
}

void PendingFile::commit() {
  struct stat st {};
  if (::lstat(target_.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw IoError(fmt::format("'{}' is no longer a regular file; the new file stays at '{}'", target_, path_));
  if (file_.held() && !file_.at(path_))
    throw IoError(
        fmt::format("'{}' is no longer the file this run wrote (replaced or removed meanwhile); '{}' is left "
                    "as it was",
                    path_, target_));
  sync_file(path_);
  if (::rename(path_.c_str(), target_.c_str()) != 0)
    throw IoError(fmt::format("cannot rename '{}' to '{}': {}", path_, target_, std::strerror(errno)));
  done_ = true;
  // the rename itself is durable once the folder is flushed
  const fs::path p(target_);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : std::string(".");
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace keller
