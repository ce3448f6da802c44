#include "runs/SolveCommand.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "continuation/start/StartSolver.hpp"
#include "core/JacobianCheck.hpp"
#include "core/Newton.hpp"
#include "core/OutputLock.hpp"
#include "core/PendingFile.hpp"
#include "core/RunFiles.hpp"
#include "core/SolutionWriter.hpp"
#include "core/SparseLU.hpp"
#include "runs/CommandRun.hpp"
#include "runs/ExitCode.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "stability/StabilityAnalysis.hpp"

namespace keller {

namespace {

// The count of unstable eigenvalues a StabilityAnalysis reports (its `unstable` column: neutral ones not counted).
long unstable_count(const PointAnalysisResult& r) { return std::lround(r.columns[r.columns.size() - 2]); }

// The spectrum of a state on the terminal: each eigenvalue, its growth rate -Re sigma, its residual.
void print_spectrum(const std::vector<EigenPair>& spectrum, const PointAnalysisResult& r) {
  if (spectrum.empty()) {
    fmt::print("stability: no finite eigenvalue (no row of the problem has a time derivative: B = 0)\n");
    return;
  }
  const long unstable = unstable_count(r);
  fmt::print("stability: {} unstable of the {} eigenvalues of J phi = sigma B phi computed nearest the shifts{}\n",
             unstable, spectrum.size(), unstable > 0 ? " (UNSTABLE)" : " (stable)");
  fmt::print("  {:>4} {:>17} {:>17} {:>10}\n", "k", "Re sigma", "Im sigma", "residual");
  for (size_t i = 0; i < spectrum.size(); ++i)
    fmt::print("  {:>4} {:>17.10e} {:>17.10e} {:>10.2e}\n", i + 1, spectrum[i].value.real(), spectrum[i].value.imag(),
               spectrum[i].residual);
  if (!r.note.empty()) fmt::print("note: {}\n", r.note);
}

// /solution/stability: the eigenvalues by real part (Re, Im, residual) and the count of unstable ones.
void write_spectrum(H5File& file, const std::string& path, const std::vector<EigenPair>& spectrum, long unstable) {
  std::vector<double> rows;
  for (const EigenPair& p : spectrum) rows.insert(rows.end(), {p.value.real(), p.value.imag(), p.residual});
  file.write_matrix(path, rows.data(), static_cast<long>(spectrum.size()), 3);
  file.set_attribute(path, "columns", std::string("sigma_re,sigma_im,residual"));
  file.set_attribute(path, "unstable", unstable);
}

// The options of a solve, as its scene sets them: [stability], [newton], [linear_solver], [start].
struct SolveSettings {
  StabilityOptions stability;
  NewtonOptions newton;
  SparseLUOptions lu;
  StartOptions start;
};

// The files a solve writes: OUT.h5 by way of its temporary, the lock, and the XDMF file beside it.
void declare_solve_outputs(RunFiles& files, const std::string& out, bool with_xdmf) {
  files.output("output file", out);
  files.temporary("output file's temporary", PendingFile::temporary_for(out));
  files.temporary("output file's lock", OutputLock::path_for(out));
  if (with_xdmf) {
    files.output("XDMF file", xdmf_path_for(out));
    files.temporary("XDMF file's temporary", PendingFile::temporary_for(xdmf_path_for(out)));
  }
}

// A branch scene solves its first steady state: its [continuation] (and [stability] where it is
// off) given keys are left aside, saying so.
void say_left_aside(const Scene& scene, const StabilityOptions& stability) {
  std::vector<std::string> ignored;
  for (const auto& [section, doc] : scene.schema().sections())
    if (section == "continuation" || (section == "stability" && !stability.enabled))
      for (const std::string& key : scene.schema().keys_in(section))
        if (scene.given(section + "." + key)) {
          ignored.push_back("[" + section + "]");
          break;
        }
  if (!ignored.empty())
    fmt::print("note: keller solve solves the scene's first steady state; {} {} for keller trace and left aside\n",
               fmt::join(ignored, " and "), ignored.size() > 1 ? "are" : "is");
}

// Newton from the problem's guess and, where it fails and the scene allows a path, again from the
// state a continuation from an easier one reaches (StartSolver); its cost on the terminal.
NewtonResult solve_state(Problem& problem, const SolveSettings& settings, NewtonSolver& newton, Vector& u) {
  u = problem.initial_guess();
  print_newton_header();
  NewtonResult res = newton.solve(u, print_newton_row);
  if (!res.converged() && settings.start.path != StartOptions::Path::Off) {
    // from an easier state by continuation (StartSolver), then Newton's table from there
    fmt::print("Newton from the initial guess failed ({}); continuing from an easier state\n", res.status.describe());
    StartSolver start(problem, settings.newton, settings.lu, settings.start,
                      [](const std::string& line) { fmt::print("{}\n", line); });
    Vector v = problem.initial_guess();
    const StartResult reached = start.reach(v);
    if (reached.status.is_ok()) {
      fmt::print("reached by {} ({} points, {} factorisations)\n", reached.path, reached.steps, reached.factorisations);
      u = std::move(v);
      res = newton.solve(u, print_newton_row);
    } else {
      fmt::print("no continuation path: {}\n", reached.status.describe());
    }
  }
  const auto& lu = newton.lu().statistics();
  fmt::print(
      "  final |F| = {:.4e} after {} iterations ({} factorisations), {:.3f} s (assembly {:.3f}, factorisation "
      "{:.3f}, solve {:.3f}, line search {:.3f})\n",
      res.residual_norm, res.iterations, res.factorisations, res.seconds, res.assembly_seconds, res.factor_seconds,
      res.solve_seconds, res.line_search_seconds);
  if (lu.factorisations > 0)
    fmt::print("  LU ({}): n = {}, nnz(A) = {}, nnz(L+U) = {:.0f} (fill {:.1f}x), ordering {}, peak {:.0f} MB\n",
               lu.backend, lu.n, lu.nnz_matrix, lu.nnz_lu, lu.nnz_lu / static_cast<double>(lu.nnz_matrix),
               lu.ordering_used, lu.peak_memory_bytes / kBytesPerMb);
  return res;
}

// OUT.h5 (by way of its temporary: all or nothing) with the state, its Newton history and its
// spectrum, then the XDMF file beside it. Throws CommandFailure (exit 3 or 4) saying what was written.
void write_solve_file(const CommandRun& run, Problem& problem, const Vector& u, const NewtonResult& res,
                      const StabilityAnalysis* analysis, long unstable) {
  SolutionFields f;
  try {
    PendingFile pending(run.out());
    {
      H5File file(pending.path(), H5File::Mode::Create);
      pending.created(file.hold());
      write_run_header(file, run.loaded(), problem);
      file.write_string("/problem/run", solve_run_record(run.loaded()));
      write_solution(file, "/solution", problem, u);
      std::vector<double> hist;
      for (const auto& it : res.history)
        hist.insert(hist.end(), {static_cast<double>(it.iteration), it.residual_norm, it.update_norm, it.step_length,
                                 it.seconds, it.assembly_seconds, it.factor_seconds, it.solve_seconds});
      file.write_matrix("/solution/newton", hist.data(), static_cast<long>(res.history.size()), 8);
      file.set_attribute("/solution/newton", "columns",
                         std::string("iteration,residual_norm,update_norm,step_length,seconds,assembly_seconds,"
                                     "factor_seconds,solve_seconds"));
      file.set_attribute("/solution/newton", "final_residual_norm", res.residual_norm);
      if (analysis) write_spectrum(file, "/solution/stability", analysis->spectrum(), unstable);
      f = problem.fields(u);
      if (f.mesh) write_mesh(file, "/mesh", *f.mesh);
      file.close();
    }
    pending.commit();
  } catch (const std::exception& e) {
    throw CommandFailure::unexpected(e, "nothing written");
  }
  try {
    if (f.mesh && run.with_fields())
      write_xdmf(xdmf_path_for(run.out()), std::filesystem::path(run.out()).filename().string(), "mesh", *f.mesh,
                 {{"solution/fields", "solution", 0.0}}, f);
  } catch (const std::exception& e) {
    throw CommandFailure::unexpected(e, fmt::format("wrote {}, but not its XDMF file", run.out()));
  }
}

}  // namespace

std::string solve_run_record(const LoadedScene& loaded) { return loaded.scene.canonical_values() + "start = solve\n"; }

int run_solve(const SolveArguments& args, RunSummary* out_summary) {
  return run_command(out_summary, [&](RunSummary& summary) {
    CommandRun run(summary);
    // 1. the scene (a branch scene: its trace sections are read and left aside), its options and the
    // files of the run: nothing is written before all are right
    SolveSettings settings;
    run.load(args.scene, args.output, declare_trace_keys, args.overrides, [&](const Scene& scene) {
      settings = {StabilityOptions::from_scene(scene), newton_options_from(scene), sparse_lu_options_from(scene),
                  StartOptions::from_scene(scene)};
    });
    run.check([&](RunFiles& files) { declare_solve_outputs(files, run.out(), run.with_fields()); }, args.output_locked);
    say_left_aside(run.scene(), settings.stability);
    Problem& problem = run.build([&](Problem& p) {
      if (settings.stability.enabled) settings.stability.check_problem(run.scene(), p);
    });
    fmt::print("problem: {}\n", problem.summary());
    if (args.check_jacobian) {
      const JacobianCheckOptions o;
      const JacobianCheckResult check = check_jacobian(problem, problem.initial_guess(), o);
      fmt::print(
          "Jacobian check against central differences of the residual (tolerance {:.0e}), from the initial "
          "guess:\n{}",
          o.tolerance, check.describe());
      if (!check.status.is_ok()) throw CommandFailure::numerical("the Jacobian check failed", check.status);
      if (!check.passed(o.tolerance))
        throw CommandFailure(
            exit_code::numerical_failure,
            fmt::format("the Jacobian check failed: an error above {:.0e} (above); no output written", o.tolerance));
      fmt::print("Jacobian check passed\n");
    }

    // 2. the steady state, and its spectrum where the scene asks for it
    NewtonSolver newton(problem, settings.newton, settings.lu);
    Vector u;
    const NewtonResult res = solve_state(problem, settings, newton, u);
    summary.unknowns = problem.size();
    summary.seconds = res.seconds;
    if (!res.converged()) throw CommandFailure::numerical("Newton failed", res.status);
    std::vector<double> obs;
    if (problem.observables(u, obs).is_ok()) {
      const auto names = problem.observable_names();
      for (size_t i = 0; i < names.size(); ++i) fmt::print("  {} = {:.10g}\n", names[i], obs[i]);
    }
    std::optional<StabilityAnalysis> analysis;
    long unstable = 0;
    if (settings.stability.enabled) {
      analysis.emplace(settings.stability, settings.lu);
      PointAnalysisResult r;
      const Status st = analysis->analyse(problem, u, r);
      if (!st.is_ok()) throw CommandFailure::numerical("the stability analysis failed", st);
      print_spectrum(analysis->spectrum(), r);
      unstable = unstable_count(r);
    }

    // 3. the file, all or nothing
    write_solve_file(run, problem, u, res, analysis ? &*analysis : nullptr, unstable);
    fmt::print("wrote {}\n", run.out());
    const auto& lu = newton.lu().statistics();
    summary.exit_code = exit_code::ok;
    summary.reason = fmt::format("converged in {} iterations", res.iterations);
    summary.output = run.out();
    summary.factorisations = res.factorisations;
    summary.solves = lu.solves;
    summary.nnz_lu = lu.nnz_lu;
    summary.lu_peak_mb = lu.peak_memory_bytes / kBytesPerMb;
    summary.lu_backend = lu.backend;
    summary.factor_seconds = res.factor_seconds;
    summary.solve_seconds = res.solve_seconds;
    return summary.exit_code;
  });
}

}  // namespace keller
