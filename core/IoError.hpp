// A file that could not be written or kept: a full disk, a file-size limit, an I/O error, a
// temporary name taken by something else, or an output replaced by another file while a run
// wrote it. The commands report it with exit code 3 (runs/ExitCode.hpp), saying what was kept.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace keller {

class IoError : public std::runtime_error {
 public:
  explicit IoError(const std::string& message) : std::runtime_error(message) {}
};

// Whether an error is a file that could not be written or kept: an IoError, or an error of
// std::filesystem (a rename, a folder that cannot be made).
inline bool is_io_failure(const std::exception& e) {
  return dynamic_cast<const IoError*>(&e) || dynamic_cast<const std::filesystem::filesystem_error*>(&e);
}

}  // namespace keller
