// A file that could not be written or kept: a full disk, a file-size limit, an I/O error, a
// temporary name taken by something else, or an output replaced by another file while a run
// wrote it. The commands report it with exit code 3 (runs/ExitCode.hpp), saying what was kept.
#pragma once

#include <stdexcept>
#include <string>

namespace keller {

class IoError : public std::runtime_error {
 public:
  explicit IoError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace keller
