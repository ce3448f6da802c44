// What a run reports besides its file: how it ended and what it cost. A study stores it for each
// task.
#pragma once

#include <string>

namespace keller {

struct RunSummary {
  int exit_code = 0;   // runs/ExitCode.hpp
  std::string reason;  // why the branch ended, or why the run failed
  std::string output;  // the file that holds the result ("" when none was written)
  long unknowns = 0;
  int points = 0, rejected = 0;
  long factorisations = 0;
  double seconds = 0;  // wall time of the continuation (or of the solve)
};

}  // namespace keller
