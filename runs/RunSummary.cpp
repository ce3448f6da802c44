#include "runs/RunSummary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "continuation/Continuation.hpp"
#include "runs/CommandFailure.hpp"
#include "runs/ExitCode.hpp"

namespace keller {

int fail_unexpected(RunSummary& summary, const std::exception& e, const std::string& kept) {
  return CommandFailure::unexpected(e, kept).report(summary);
}

bool takes_its_name(bool interrupted, bool failed, const std::string& out) {
  return !interrupted && !(failed && std::filesystem::exists(out));
}

std::optional<int> stays_unfinished(bool interrupted, bool failed, const std::string& work, const std::string& out,
                                    const std::string& what, const std::string& short_of, RunSummary& summary) {
  if (interrupted) {
    fmt::print("interrupted: the {} so far is in {}; run the same command again to continue it\n", what, work);
    summary.output = work;
    summary.exit_code = exit_code::interrupted;
    return summary.exit_code;
  }
  summary.exit_code = failed ? exit_code::numerical_failure : exit_code::ok;
  if (failed && std::filesystem::exists(out)) {
    fmt::print("the {} ended {}; {} is kept as it was, this run's {} is in {}\n", what, short_of, out, what, work);
    summary.output = work;
    return summary.exit_code;
  }
  return std::nullopt;
}

void report_branch_run(const ContinuationResult& result, long unknowns, RunSummary& summary) {
  fmt::print(
      "{} points, {} rejected steps, {} factorisations ({:.2f} per point; {} of them branch-point probes), {} "
      "tangent solves by iteration, renewal cost {:.1f} solves; {}\n",
      result.points, result.rejected, result.factorisations,
      result.points > 0 ? static_cast<double>(result.factorisations) / result.points : 0.0, result.probes,
      result.tangent_iterations, result.renewal_cost, result.reason);
  const ContinuationTimings& tm = result.timings;
  fmt::print(
      "time {:.2f} s: factorisations {:.2f}, solves {:.2f} ({}), Jacobians {:.2f} ({}), dF/dp {:.2f}, residuals {:.2f} "
      "({}), "
      "observables {:.2f}, stability {:.2f} ({} spectra), output {:.2f}, other {:.2f}\n",
      tm.total, tm.factorisation, tm.solve, tm.solves, tm.jacobian, tm.jacobians, tm.parameter_derivative, tm.residual,
      tm.residuals, tm.observables, tm.analysis, tm.analyses, tm.output,
      tm.total - tm.factorisation - tm.solve - tm.jacobian - tm.parameter_derivative - tm.residual - tm.observables -
          tm.analysis - tm.output);
  if (!result.lu_backend.empty())
    fmt::print("LU: {}, nnz(L+U) = {:.4g}, peak {:.0f} MB\n", result.lu_backend, result.nnz_lu,
               result.lu_peak_bytes / kBytesPerMb);
  summary.reason = result.reason;
  summary.unknowns = unknowns;
  summary.points = result.points;
  summary.rejected = result.rejected;
  summary.factorisations = result.factorisations;
  summary.seconds = result.timings.total;
  summary.solves = result.timings.solves;
  summary.nnz_lu = result.nnz_lu;
  summary.lu_peak_mb = result.lu_peak_bytes / kBytesPerMb;
  summary.lu_backend = result.lu_backend;
  summary.factor_seconds = result.timings.factorisation;
  summary.solve_seconds = result.timings.solve;
}

void add_earlier_runs(RunSummary& now, const RunSummary* earlier) {
  if (now.continued_from < 0) return;
  now.points += now.continued_from;  // (the run's first row is the earlier runs' last)
  now.runs = (earlier ? earlier->runs : 1) + 1;
  if (!earlier) return;
  now.rejected += earlier->rejected;
  now.factorisations += earlier->factorisations;
  now.solves += earlier->solves;
  now.seconds += earlier->seconds;
  now.factor_seconds += earlier->factor_seconds;
  now.solve_seconds += earlier->solve_seconds;
  now.lu_peak_mb = std::max(now.lu_peak_mb, earlier->lu_peak_mb);
  if (now.lu_backend.empty()) {  // a run that only published: the last factorisation was theirs
    now.lu_backend = earlier->lu_backend;
    now.nnz_lu = earlier->nnz_lu;
  }
  if (now.unknowns == 0) now.unknowns = earlier->unknowns;
}

}  // namespace keller
