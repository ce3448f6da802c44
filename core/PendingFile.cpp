#include "core/PendingFile.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace keller {

namespace fs = std::filesystem;

void sync_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) throw std::runtime_error(fmt::format("cannot open '{}' to flush it: {}", path, std::strerror(errno)));
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw std::runtime_error(fmt::format("cannot flush '{}' to disk: {}", path, std::strerror(errno)));
}

PendingFile::PendingFile(std::string target) : target_(std::move(target)), path_(temporary_for(target_)) {}

std::string PendingFile::temporary_for(const std::string& target) { return target + ".part"; }

PendingFile::~PendingFile() {
  if (done_) return;
  std::error_code ec;
  fs::remove(path_, ec);
}

void PendingFile::commit() {
  struct stat st {};
  if (::lstat(target_.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw std::runtime_error(
        fmt::format("'{}' is no longer a regular file; the new file stays at '{}'", target_, path_));
  sync_file(path_);
  if (::rename(path_.c_str(), target_.c_str()) != 0)
    throw std::runtime_error(fmt::format("cannot rename '{}' to '{}': {}", path_, target_, std::strerror(errno)));
  done_ = true;
  // the rename itself is durable once the folder is flushed
  const fs::path p(target_);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : std::string(".");
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace keller
