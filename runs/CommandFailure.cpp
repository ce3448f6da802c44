#include "runs/CommandFailure.hpp"

#include <fmt/format.h>

#include <cstdio>

#include "core/IoError.hpp"
#include "runs/ExitCode.hpp"

namespace keller {

CommandFailure::CommandFailure(int code, std::string line, std::string reason)
    : std::runtime_error(reason), code_(code), line_(std::move(line)), reason_(std::move(reason)) {}

CommandFailure::CommandFailure(int code, const std::string& message)
    : CommandFailure(code, "keller: error: " + message, message) {}

CommandFailure CommandFailure::bad_input(const std::string& message) { return {exit_code::usage, message}; }

CommandFailure CommandFailure::io_failure(const std::string& message) { return {exit_code::io_failure, message}; }

CommandFailure CommandFailure::numerical(const std::string& what, const Status& status) {
  return {exit_code::numerical_failure, fmt::format("keller: {}: {}; no output written", what, status.describe()),
          what + ": " + status.describe()};
}

CommandFailure CommandFailure::unexpected(const std::exception& error, const std::string& kept) {
  const std::string also = kept.empty() ? "" : "; " + kept;
  if (is_io_failure(error)) return io_failure(error.what() + also);
  const std::string message = fmt::format(
      "{}{}; this is a defect of keller: please report it, with the command and this message", error.what(), also);
  return {exit_code::internal_error, "keller: internal error: " + message, "internal error: " + message};
}

int CommandFailure::report(RunSummary& summary) const {
  fmt::print(stderr, "{}\n", line_);
  summary.exit_code = code_;
  summary.reason = reason_;
  return code_;
}

}  // namespace keller
