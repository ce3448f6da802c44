// Why a command stops before its end, and what it says: the exit code (runs/ExitCode.hpp), the
// line it prints on stderr and the reason a study records (RunSummary::reason). Any phase of a
// command throws it; run_command (runs/CommandRun.hpp) reports it, the one place that does.
#pragma once

#include <exception>
#include <stdexcept>
#include <string>

#include "core/Status.hpp"
#include "runs/RunSummary.hpp"

namespace keller {

class CommandFailure : public std::runtime_error {
 public:
  // "keller: error: MESSAGE" with the exit code `code`; the reason is the message.
  CommandFailure(int code, const std::string& message);

  // Bad command line, scene, path or stored start (exit 2): nothing was written.
  static CommandFailure bad_input(const std::string& message);
  // A file that could not be written or kept (exit 3); the message says what was kept.
  static CommandFailure io_failure(const std::string& message);
  // A numerical failure before anything is written (exit 1): "keller: WHAT: STATUS; no output
  // written", the reason "WHAT: STATUS".
  static CommandFailure numerical(const std::string& what, const Status& status);
  // An error that has no message of its own in the command: exit 3 where a file could not be
  // written or kept (is_io_failure), else exit 4, a defect of keller, whose message asks for a
  // report. `kept` ("the branch stays in OUT.h5.part") says what was kept.
  static CommandFailure unexpected(const std::exception& error, const std::string& kept = "");

  int code() const { return code_; }
  // The line on stderr, without its end of line.
  const std::string& line() const { return line_; }
  const std::string& reason() const { return reason_; }
  // Prints the line on stderr, gives `summary` the code and the reason; returns the code.
  int report(RunSummary& summary) const;

 private:
  CommandFailure(int code, std::string line, std::string reason);
  int code_;
  std::string line_, reason_;
};

}  // namespace keller
