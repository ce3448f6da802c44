#include "continuation/output/RunFile.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/IoError.hpp"
#include "core/PendingFile.hpp"
#include "core/SignalPoint.hpp"

namespace keller {

RunFile::RunFile(const std::string& path, const std::string& group, const std::function<void(H5File&)>& layout)
    : group_(group) {
  const std::string part = PendingFile::temporary_for(path);
  clear_leftover(part);
  file_ = std::make_unique<H5File>(part, H5File::Mode::Create);
  written_ = file_->hold();
  try {
    layout(*file_);
    file_->create_fixed_string(group + "/status", 2048);
    file_->write_fixed_string(group + "/status", "running");
    file_->create_appendable(group + "/exit_code", 1, 1);
    const double unmarked = -1;
    file_->append_rows(group + "/exit_code", &unmarked, 1);
    file_->start_swmr();
    file_->flush();
    if (!written_.at(part))
      throw IoError(fmt::format("'{}' is not the file this run created (it was replaced meanwhile)", part));
    if (std::rename(part.c_str(), path.c_str()) != 0)
      throw IoError(fmt::format("cannot rename '{}' to '{}': {}", part, path, std::strerror(errno)));
    file_->renamed(path);
  } catch (...) {
    // this run's incomplete file: nothing of it is kept
    file_.reset();
    std::error_code ec;
    if (written_.at(part)) std::filesystem::remove(part, ec);
    throw;
  }
}

RunFile::~RunFile() {
  try {
    close();
  } catch (const std::exception&) {  // a destructor must not throw; close() reports it when called directly
  }
}

void RunFile::close() {
  if (file_) file_->close();
  file_.reset();
}

void RunFile::ended(const std::string& reason) {
  file_->flush();
  reason_ = reason;
  signal_point("ended");
}

void RunFile::finish(std::optional<int> publication_code) {
  if (!file_) return;
  if (publication_code) {
    const double code = *publication_code;
    file_->write_rows(group_ + "/exit_code", 0, &code, 1);
  }
  file_->write_fixed_string(group_ + "/status", reason_);
  file_->flush();
  close();
}

}  // namespace keller
