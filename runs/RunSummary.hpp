// What a run reports besides its file: how it ended and what it cost. A study stores it for each
// task.
#pragma once

#include <optional>
#include <string>

namespace keller {

struct ContinuationResult;

inline constexpr double kBytesPerMb = 1024.0 * 1024.0;  // memory is reported in MiB

struct RunSummary {
  int exit_code = 0;   // runs/ExitCode.hpp
  std::string reason;  // why the branch ended, or why the run failed
  std::string output;  // the file that holds the result ("" when none was written)
  long unknowns = 0;
  int points = 0, rejected = 0;
  long factorisations = 0;
  double seconds = 0;  // wall time of the continuation (or of the solve)
  // what the linear algebra cost: the sparse LU ("umfpack", "mumps"), solves with the
  // factorisations, nonzeros of L + U of the last factorisation (fill), its peak memory, and the
  // time in factorisations and solves
  std::string lu_backend;
  long solves = 0;
  double nnz_lu = 0, lu_peak_mb = 0;
  double factor_seconds = 0, solve_seconds = 0;
  // the row of an unfinished output of interrupted runs that this run continued (-1: none; its
  // last row for a run that only published an ended one); the runs whose work the output holds,
  // and then the cost above may be theirs together (add_earlier_runs)
  int continued_from = -1;
  int runs = 1;
};

// What a branch's run reports: the lines of its cost on the terminal (points, rejected steps,
// factorisations, ...; where its time went; the LU) and, in `summary`, why it ended and its cost
// (`unknowns` its problem's).
void report_branch_run(const ContinuationResult& result, long unknowns, RunSummary& summary);

// `now`, the cost of a run that continued an unfinished output (continued_from), plus `earlier`,
// the cost of the runs that made that output (nothing where they left none: a run killed
// outright): counts and times added, the points the rows of the output, the peak memory the
// larger, the last factorisation's fill this run's (theirs for a run that only published their
// output: publish_left_run).
void add_earlier_runs(RunSummary& now, const RunSummary* earlier);

// Reports an error that has no message of its own in the command (caught as std::exception) and
// returns its exit code: 3 where a file could not be written or kept (is_io_failure), else 4, a
// defect of keller, whose message asks for a report (CommandFailure::unexpected). `kept` ("the
// branch stays in OUT.h5.part") says what was kept.
int fail_unexpected(RunSummary& summary, const std::exception& e, const std::string& kept = "");

// Whether an ended run takes its name: not when interrupted (it is continued), nor when it failed
// and `out` exists (a failing run never replaces a result).
bool takes_its_name(bool interrupted, bool failed, const std::string& out);

// The end of a run written to `work` (OUT.part) that takes the name `out` once complete: an
// interrupted run stays in `work`, to be continued by the same command (exit 130), and a failed one
// (exit 1) never replaces an existing `out`. Returns the exit code where the file stays in `work`
// (saying so, `what` naming the content: "branch", "time series"; `short_of` why it ended early),
// nothing where it is to take its name; `summary` gets the code and the file.
std::optional<int> stays_unfinished(bool interrupted, bool failed, const std::string& work, const std::string& out,
                                    const std::string& what, const std::string& short_of, RunSummary& summary);

}  // namespace keller
