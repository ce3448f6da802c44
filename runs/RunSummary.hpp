// What a run reports besides its file: how it ended and what it cost. A study stores it for each
// task.
#pragma once

#include <string>

namespace keller {

inline constexpr double kBytesPerMb = 1024.0 * 1024.0;  // memory is reported in MiB

struct RunSummary {
  int exit_code = 0;   // runs/ExitCode.hpp
  std::string reason;  // why the branch ended, or why the run failed
  std::string output;  // the file that holds the result ("" when none was written)
  long unknowns = 0;
  int points = 0, rejected = 0;
  long factorisations = 0;
  double seconds = 0;  // wall time of the continuation (or of the solve)
  // what the linear algebra cost: solves with the factorisations, nonzeros of L + U of the last
  // factorisation (fill), UMFPACK's peak memory for it, and the time in factorisations and solves
  long solves = 0;
  double nnz_lu = 0, lu_peak_mb = 0;
  double factor_seconds = 0, solve_seconds = 0;
};

}  // namespace keller
