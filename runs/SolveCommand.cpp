#include "runs/SolveCommand.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "continuation/start/StartSolver.hpp"
#include "core/Newton.hpp"
#include "core/OutputLock.hpp"
#include "core/PendingFile.hpp"
#include "core/RunFiles.hpp"
#include "core/SolutionWriter.hpp"
#include "core/SparseLU.hpp"
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

}  // namespace

std::string solve_run_record(const LoadedScene& loaded) { return loaded.scene.canonical_values() + "start = solve\n"; }

int run_solve(const SolveArguments& args, RunSummary* out_summary) {
  RunSummary local;
  RunSummary& summary = out_summary ? *out_summary : local;
  summary = {};
  auto fail = [&](int code, const std::string& message) {
    fmt::print(stderr, "keller: error: {}\n", message);
    summary.exit_code = code;
    summary.reason = message;
    return code;
  };
  namespace fs = std::filesystem;
  LoadedScene loaded;
  std::unique_ptr<Problem> problem;
  std::string out = args.output;
  try {
    // a branch scene solves its first state: the trace sections are read and left aside
    loaded = load_scene(args.scene, declare_trace_keys, args.overrides);
    check_memory(loaded);
  } catch (const SceneError& e) {
    return fail(exit_code::usage, e.what());
  }
  if (out.empty()) out = fs::path(args.scene).stem().string() + ".h5";
  const bool with_xdmf = loaded.scene.boolean("output.xdmf");
  OutputLock lock;  // one run at a time writes `out`
  try {
    RunFiles files;
    files.input("scene file", args.scene);
    files.output("output file", out);
    files.temporary("output file's temporary", PendingFile::temporary_for(out));
    files.temporary("output file's lock", OutputLock::path_for(out));
    if (with_xdmf) {
      files.output("XDMF file", xdmf_path_for(out));
      files.temporary("XDMF file's temporary", PendingFile::temporary_for(xdmf_path_for(out)));
    }
    files.check();
    if (!args.output_locked) lock = OutputLock(OutputLock::path_for(out), "'" + out + "'");
  } catch (const std::exception& e) {
    return fail(exit_code::usage, e.what());
  }
  StabilityOptions stability;
  try {
    stability = StabilityOptions::from_scene(loaded.scene);
  } catch (const SceneError& e) {
    return fail(exit_code::usage, e.what());
  }
  std::vector<std::string> ignored;
  for (const auto& [section, doc] : loaded.scene.schema().sections())
    if (section == "continuation" || (section == "stability" && !stability.enabled))
      for (const std::string& key : loaded.scene.schema().keys_in(section))
        if (loaded.scene.given(section + "." + key)) {
          ignored.push_back("[" + section + "]");
          break;
        }
  fmt::print("{}\n", scene_summary(loaded, out));
  if (!ignored.empty())
    fmt::print("note: keller solve solves the scene's first steady state; {} {} for keller trace and left aside\n",
               fmt::join(ignored, " and "), ignored.size() > 1 ? "are" : "is");
  try {
    problem = loaded.type->build(loaded.scene);
    if (stability.enabled) stability.check_size(loaded.scene, problem->size());
  } catch (const SceneError& e) {
    return fail(exit_code::usage, e.what());
  } catch (const std::exception& e) {
    return fail(exit_code::usage, fmt::format("{}: {}", args.scene, e.what()));
  }
  const Scene& scene = loaded.scene;
  fmt::print("problem: {}\n", problem->summary());

  NewtonSolver newton(*problem, newton_options_from(scene), sparse_lu_options_from(scene));
  Vector u = problem->initial_guess();
  print_newton_header();
  NewtonResult res = newton.solve(u, print_newton_row);
  const StartOptions start_options = StartOptions::from_scene(scene);
  if (!res.converged() && start_options.path != StartOptions::Path::Off) {
    // from an easier state by continuation (StartSolver), then Newton's table from there
    fmt::print("Newton from the initial guess failed ({}); continuing from an easier state\n", res.status.describe());
    StartSolver start(*problem, newton_options_from(scene), sparse_lu_options_from(scene), start_options,
                      [](const std::string& line) { fmt::print("{}\n", line); });
    Vector v = problem->initial_guess();
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
  if (!res.converged()) {
    fmt::print(stderr, "keller: Newton failed: {}; no output written\n", res.status.describe());
    summary.exit_code = exit_code::numerical_failure;
    summary.reason = "Newton failed: " + res.status.describe();
    summary.unknowns = problem->size();
    summary.seconds = res.seconds;
    return summary.exit_code;
  }

  std::vector<double> obs;
  if (problem->observables(u, obs).is_ok()) {
    const auto names = problem->observable_names();
    for (size_t i = 0; i < names.size(); ++i) fmt::print("  {} = {:.10g}\n", names[i], obs[i]);
  }

  // the spectrum of the state, where the scene asks for it
  std::optional<StabilityAnalysis> analysis;
  long unstable = 0;
  if (stability.enabled) {
    analysis.emplace(stability, sparse_lu_options_from(scene));
    PointAnalysisResult r;
    const Status st = analysis->analyse(*problem, u, r);
    if (!st.is_ok()) {
      fmt::print(stderr, "keller: the stability analysis failed: {}; no output written\n", st.describe());
      summary.exit_code = exit_code::numerical_failure;
      summary.reason = "stability analysis failed: " + st.describe();
      return summary.exit_code;
    }
    print_spectrum(analysis->spectrum(), r);
    unstable = unstable_count(r);
  }

  SolutionFields f;
  try {
    PendingFile pending(out);
    {
      H5File file(pending.path(), H5File::Mode::Create);
      pending.created(file.hold());
      write_run_header(file, loaded, *problem);
      file.write_string("/problem/run", solve_run_record(loaded));
      write_solution(file, "/solution", *problem, u);
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
      f = problem->fields(u);
      if (f.mesh) write_mesh(file, "/mesh", *f.mesh);
      file.close();
    }
    pending.commit();
  } catch (const std::exception& e) {
    return fail_unexpected(summary, e, "nothing written");
  }
  try {
    if (f.mesh && with_xdmf)
      write_xdmf(xdmf_path_for(out), fs::path(out).filename().string(), "mesh", *f.mesh,
                 {{"solution/fields", "solution", 0.0}}, f);
  } catch (const std::exception& e) {
    return fail_unexpected(summary, e, fmt::format("wrote {}, but not its XDMF file", out));
  }
  fmt::print("wrote {}\n", out);
  summary.exit_code = exit_code::ok;
  summary.reason = fmt::format("converged in {} iterations", res.iterations);
  summary.output = out;
  summary.unknowns = problem->size();
  summary.factorisations = res.factorisations;
  summary.seconds = res.seconds;
  summary.solves = lu.solves;
  summary.nnz_lu = lu.nnz_lu;
  summary.lu_peak_mb = lu.peak_memory_bytes / kBytesPerMb;
  summary.lu_backend = lu.backend;
  summary.factor_seconds = res.factor_seconds;
  summary.solve_seconds = res.solve_seconds;
  return summary.exit_code;
}

}  // namespace keller
