#include "core/RunFiles.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

namespace keller {

namespace fs = std::filesystem;

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {
  }, sb{};
  const bool ea = ::stat(a.c_str(), &sa) == 0, eb = ::stat(b.c_str(), &sb) == 0;
  if (ea && eb) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  if (ea != eb) return false;
  std::error_code ec1, ec2;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a), ec1), cb = fs::weakly_canonical(fs::absolute(b), ec2);
  if (ec1 || ec2) return fs::absolute(a).lexically_normal() == fs::absolute(b).lexically_normal();
  return ca == cb;
}

void RunFiles::input(std::string role, std::string path) { inputs_.push_back({std::move(role), std::move(path)}); }

void RunFiles::output(std::string role, std::string path) { outputs_.push_back({std::move(role), std::move(path)}); }

void RunFiles::temporary(std::string role, std::string path) {
  outputs_.push_back({std::move(role), std::move(path), true});
}

namespace {

// What a path that exists is, when it is not a regular file ("" when it is one or is absent); a
// temporary name must not be a hard link either.
std::string not_regular(const std::string& path, bool temporary) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return "";
  if (S_ISREG(st.st_mode) && temporary && st.st_nlink > 1)
    return "a hard link to another file (keller creates its temporary files itself; move it away)";
  if (S_ISREG(st.st_mode)) return "";
  if (S_ISLNK(st.st_mode)) return "a symbolic link (give the path it points to, or another name)";
  if (S_ISDIR(st.st_mode)) return "a directory";
  if (S_ISFIFO(st.st_mode)) return "a FIFO";
  if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "a device";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

void RunFiles::check() const {
  for (size_t i = 0; i < outputs_.size(); ++i) {
    const Entry& o = outputs_[i];
    if (o.path.empty()) throw std::invalid_argument(fmt::format("{}: empty path", o.role));
    for (const Entry& in : inputs_)
      if (same_file(o.path, in.path))
        throw std::invalid_argument(
            fmt::format("{} '{}' is the same file as the {} '{}': it would be overwritten; "
                        "write to another file",
                        o.role, o.path, in.role, in.path));
    for (size_t j = 0; j < i; ++j)
      if (same_file(o.path, outputs_[j].path))
        throw std::invalid_argument(fmt::format("{} '{}' and {} '{}' are the same file; give them different names",
                                                outputs_[j].role, outputs_[j].path, o.role, o.path));
    const std::string what = not_regular(o.path, o.temporary);
    if (!what.empty())
      throw std::invalid_argument(fmt::format("{} '{}' is {}: keller writes only regular files", o.role, o.path, what));
    const fs::path p(o.path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
      throw std::invalid_argument(fmt::format("{} '{}': folder '{}' does not exist", o.role, o.path, dir.string()));
    if (::access(dir.c_str(), W_OK) != 0)
      throw std::invalid_argument(fmt::format("{} '{}': folder '{}' is not writable", o.role, o.path, dir.string()));
  }
}

}  // namespace keller
