// Benchmark (not a test): what a continuation run costs per point, and what eigenvalue monitoring
// adds to it. Goals: a continuation point of the collapsible channel on M2 in under 1 s (issue 5);
// 6 eigenvalues at every point add at most 25% to the run (issue 6).
//
// The same scene is traced twice from the same first steady state: once without spectra, once with
// [stability] enabled (every = N). The second run's extra time is the monitoring's cost; the
// eigen-solver's solves per spectrum and the time of one solve say where it goes and what the
// cheapest possible spectrum (one Arnoldi basis of ncv vectors, no restart) would cost.
//
// Usage: bench_trace [SCENE.toml] [--steps N] [--every N] [--no-spectra] [--set section.key=value]...
//   SCENE defaults to runs/scenes/collapsible_oldroyd_b_gamma.toml (M2, Oldroyd-B, Gamma branch).
#include <fmt/format.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <vector>

#include "continuation/Continuation.hpp"
#include "core/Newton.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "stability/StabilityAnalysis.hpp"

using namespace keller;

namespace {

struct CountRows final : BranchObserver {
  int rows = 0;
  void on_point(const BranchPoint&) override { ++rows; }
};

struct RunFigures {
  ContinuationResult result;
  int rows = 0;
  double seconds = 0;
  double eig_seconds = 0;
  long eig_solves = 0, eig_factorisations = 0, spectra = 0;
};

RunFigures trace(Problem& problem, const Vector& u0, const ContinuationOptions& copt, const NewtonOptions& nopt,
                 const SparseLUOptions& lopt, const StabilityOptions* sopt) {
  RunFigures f;
  ContinuationOptions o = copt;
  const double rms = u0.norm() / std::sqrt(static_cast<double>(std::max<long>(u0.size(), 1)));
  if (!(o.state_scale > 0)) o.state_scale = rms > 0 ? rms : 1.0;
  Continuation run(problem, o, nopt, lopt);
  std::unique_ptr<StabilityAnalysis> stability;
  if (sopt) {
    stability = std::make_unique<StabilityAnalysis>(*sopt, lopt);
    run.set_analysis(stability.get());
  }
  CountRows rows;
  const auto t0 = std::chrono::steady_clock::now();
  f.result = run.run(u0, rows);
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  f.rows = rows.rows;
  if (stability) {
    f.eig_seconds = stability->seconds();
    f.eig_solves = stability->solves();
    f.eig_factorisations = stability->factorisations();
    f.spectra = f.result.timings.analyses;
  }
  return f;
}

void print_run(const std::string& label, const RunFigures& f) {
  const ContinuationTimings& t = f.result.timings;
  const int steps = std::max(f.rows - 1, 1);  // rows after the start (steps and located points)
  fmt::print("{:<22} {:>5} {:>6} {:>7} {:>8.2f} {:>8.3f} {:>9.2f} {:>8.2f} {:>7.2f} {:>8.2f} {:>8.2f}  {}\n", label,
             f.rows, f.result.factorisations, t.solves, f.seconds, f.seconds / steps, t.factorisation, t.solve,
             t.jacobian, t.analysis,
             f.seconds - t.factorisation - t.solve - t.jacobian - t.analysis, f.result.reason);
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene = std::string(KELLER_SOURCE_DIR) + "/runs/scenes/collapsible_oldroyd_b_gamma.toml";
  int steps = 6, every = 1;
  bool spectra = true;
  std::vector<std::string> overrides;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
      return argv[++i];
    };
    if (a == "--steps") steps = std::stoi(next());
    else if (a == "--every") every = std::stoi(next());
    else if (a == "--no-spectra") spectra = false;
    else if (a == "--set") overrides.push_back(next());
    else if (!a.empty() && a[0] != '-') scene = a;
    else {
      fmt::print(stderr, "unknown argument {}\n", a);
      return 2;
    }
  }
  overrides.push_back(fmt::format("continuation.max_steps={}", steps));
  LoadedScene loaded;
  try {
    loaded = load_scene(scene, declare_trace_keys, overrides);
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_trace: {}\n", e.what());
    return 2;
  }
  auto problem = loaded.type->build(loaded.scene);
  const ContinuationOptions copt = ContinuationOptions::from_scene(loaded.scene);
  StabilityOptions sopt = StabilityOptions::from_scene(loaded.scene);
  sopt.enabled = true;
  sopt.every = every;
  const NewtonOptions nopt = newton_options_from(loaded.scene);
  const SparseLUOptions lopt = sparse_lu_options_from(loaded.scene);
  const char* threads = std::getenv("OPENBLAS_NUM_THREADS");
  fmt::print("{}\n{}\nparameter {}, {} steps, BLAS threads {}\n", scene, problem->summary(), copt.parameter, steps,
             threads ? threads : "default (all cores)");

  Vector u0 = problem->initial_guess();
  NewtonSolver newton(*problem, nopt, lopt);
  const auto t0 = std::chrono::steady_clock::now();
  const NewtonResult r = newton.solve(u0);
  if (!r.converged()) {
    fmt::print(stderr, "first steady state failed: {}\n", r.status.describe());
    return 1;
  }
  const double start_value = problem->parameters().get(copt.parameter);
  fmt::print("first steady state: {} Newton iterations ({} factorisations), {:.2f} s (not in the runs below)\n\n", r.iterations, r.factorisations,
             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());

  fmt::print("{:<22} {:>5} {:>6} {:>7} {:>8} {:>8} {:>9} {:>8} {:>7} {:>8} {:>8}  {}\n", "run", "rows", "factor",
             "solves", "total s", "s/row", "factor s", "solve s", "jac s", "spectra", "other s", "end");
  const RunFigures plain = trace(*problem, u0, copt, nopt, lopt, nullptr);
  print_run("continuation only", plain);
  if (!spectra) return 0;
  problem->parameters().set(copt.parameter, start_value);
  const RunFigures with = trace(*problem, u0, copt, nopt, lopt, &sopt);
  print_run(fmt::format("{} eigs, every {}", sopt.count, every), with);

  const double solve_s = with.eig_solves > 0 ? with.eig_seconds / with.eig_solves : 0;
  // EigenOptions::ncv's default (capped by n)
  const int ncv = std::min(sopt.ncv > 0 ? sopt.ncv : std::max(2 * sopt.count + 1, 20), problem->size());
  const double point_s = plain.seconds / std::max(plain.rows - 1, 1);
  fmt::print("\nmonitoring adds {:+.0f}% (issue 6's goal: <= +25%): {} spectra in {:.2f} s, {} eigen-solver factorisations, "
             "{:.0f} solves per spectrum at {:.1f} ms each\n",
             100.0 * (with.seconds - plain.seconds) / plain.seconds, with.spectra, with.eig_seconds,
             with.eig_factorisations, with.spectra ? static_cast<double>(with.eig_solves) / with.spectra : 0.0,
             1e3 * solve_s);
  fmt::print("a spectrum costs at least one Arnoldi basis, ncv = {} solves = {:.2f} s = {:.0f}% of a point "
             "({:.2f} s); the 25% goal allows {:.0f} solves per point\n",
             ncv, ncv * solve_s, 100.0 * ncv * solve_s / point_s, point_s, solve_s > 0 ? 0.25 * point_s / solve_s : 0.0);
  return 0;
}
