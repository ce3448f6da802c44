// Benchmark (not a test): what the normal form of a located Hopf point costs against one spectrum
// at the same point. Goal (issue 36): at most one spectrum, on M2.
//
// The point is read from a branch file (a trace with [stability] that located it), the scene's
// parameters set to the point's. Timed, --repeat times each, alternating, and the median printed:
// - the spectrum as the scene's [stability] computes it, with J factorised for it (a trace reuses
//   Newton's factorisation where its shift is 0: the J factorisation, timed on its own, is then
//   not part of the spectrum's cost, and the line "spectrum without J's factorisation" is that);
// - the normal form as the trace's observer computes it, with its factorisations, derivatives and
//   their times; and with every solve on a factorisation of its own (NormalForms'
//   krylov_iterations = 0), whose l1 the first must reproduce.
//
// Usage: bench_normal_form SCENE.toml BRANCH.h5:LABEL [--repeat N] [--eigenvalues N] [--set section.key=value]...
//   --eigenvalues N also prints how many of the N eigenvalues nearest 0 lie within 1, 2 and 3
//   omega: the modes that GMRES on J's factorisation pays for.
//   The M2 Hopf point of docs/normal_forms.md:
//   bench_normal_form runs/scenes/stability_collapsible_newtonian_re.toml re_M2.h5:hopf1
//       --set parameters.Gamma=4.95e-5 --set 'mesh.name="M2"'
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "continuation/output/BranchFile.hpp"
#include "core/SparseLU.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/StoredStart.hpp"
#include "runs/TraceCommand.hpp"
#include "runs/TraceStart.hpp"
#include "stability/EigenSolver.hpp"
#include "stability/NormalForms.hpp"
#include "stability/StabilityAnalysis.hpp"

using namespace keller;

namespace {

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void print_machine() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string line, model = "?";
  while (std::getline(cpu, line))
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  const char* threads = std::getenv("OPENBLAS_NUM_THREADS");
  fmt::print("machine: {}, {} hardware threads, OPENBLAS_NUM_THREADS={}\n", model, std::thread::hardware_concurrency(),
             threads ? threads : "(unset)");
}

int usage() {
  fmt::print(stderr,
             "usage: bench_normal_form SCENE.toml BRANCH.h5:LABEL [--repeat N] [--eigenvalues N] "
             "[--set section.key=value]...\n");
  return 2;
}

// The `count` eigenvalues nearest 0 against omega: each costs GMRES on J's factorisation about an
// iteration where |sigma| is within a few omega (NormalFormSolvers.hpp, RealLUShiftSolver).
void print_eigenvalues_near_zero(Problem& problem, const Vector& u, const SparseLUOptions& lu, int count,
                                 double omega) {
  SparseMatrix J = problem.jacobian_pattern(), B = problem.jacobian_pattern();
  Vector F;
  if (!problem.jacobian(u, F, J).is_ok() || !problem.mass_matrix(u, B).is_ok())
    throw std::runtime_error("J or B failed at the point");
  EigenOptions options;
  options.count = count;
  EigenResult result;
  if (Status st = EigenSolver(lu).solve(J, B, options, result); !st.is_ok())
    throw std::runtime_error("the eigenvalues near 0 failed: " + st.message());
  std::vector<double> ratios;
  for (const EigenPair& pair : result.pairs) ratios.push_back(std::abs(pair.value) / omega);
  std::sort(ratios.begin(), ratios.end());
  int within[3] = {0, 0, 0};
  for (double r : ratios)
    for (int k = 0; k < 3; ++k) within[k] += r <= k + 1 + 1e-9;
  fmt::print(
      "the {} eigenvalues nearest 0: {} within omega, {} within 2 omega, {} within 3 omega; |sigma| / omega {:.3g} to "
      "{:.3g}\n",
      ratios.size(), within[0], within[1], within[2], ratios.empty() ? 0.0 : ratios.front(),
      ratios.empty() ? 0.0 : ratios.back());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string scene_path = argv[1], spec = argv[2];
  int repeat = 3, eigenvalues = 0;
  std::vector<std::string> overrides;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeat" && i + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--eigenvalues" && i + 1 < argc)
      eigenvalues = std::max(1, std::atoi(argv[++i]));
    else if (a == "--set" && i + 1 < argc)
      overrides.emplace_back(argv[++i]);
    else
      return usage();
  }
  try {
    print_machine();
    const LoadedScene loaded = load_scene(scene_path, declare_trace_keys, overrides);
    const TraceSettings settings = TraceSettings::from_scene(loaded.scene);
    auto problem = loaded.type->build(loaded.scene);
    const std::string parameter = settings.continuation.parameter;
    std::vector<std::string> warnings;
    const StoredStart start = parse_stored_start("point", spec);
    const StoredPoint stored = read_stored_start(start, loaded, *problem, parameter, warnings);
    if (stored.point.kind != PointKind::Hopf) {
      fmt::print(stderr, "{} is not a Hopf point\n", spec);
      return 2;
    }
    use_stored_parameters(*problem, stored);
    const int p = problem->parameters().index(parameter);
    problem->parameters().set(p, stored.point.lambda);
    const Vector& u = stored.point.u;
    // the critical eigenvector and frequency, as the trace's observer had them
    const std::optional<StoredMode> mode = read_branch_mode(start.file, stored.point.index);
    if (!mode || mode->re.size() != u.size()) throw std::runtime_error(spec + ": no critical eigenvector stored");
    Eigen::VectorXcd guess = mode->re.cast<std::complex<double>>();
    if (mode->im.size() == u.size()) guess += std::complex<double>(0.0, 1.0) * mode->im;
    const double omega = std::abs(mode->sigma_im);
    fmt::print("{} unknowns, {} = {:.10g}, omega = {:.6g}; spectrum: {} eigenvalues\n", problem->size(), parameter,
               stored.point.lambda, omega, settings.stability.count);

    if (eigenvalues > 0) print_eigenvalues_near_zero(*problem, u, settings.lu, eigenvalues, omega);
    std::vector<double> spectrum_s, factor_s, form_s, form_factor_s, form_derivative_s, direct_s;
    NormalForm direct;
    NormalForm nf;
    for (int k = 0; k < repeat; ++k) {
      {
        SparseMatrix J = problem->jacobian_pattern();
        Vector F;
        if (!problem->jacobian(u, F, J).is_ok()) throw std::runtime_error("the Jacobian failed at the point");
        SparseLU lu(settings.lu);
        const auto t0 = std::chrono::steady_clock::now();
        if (!lu.factorize(J).is_ok()) throw std::runtime_error("J's factorisation failed at the point");
        factor_s.push_back(since(t0));
      }
      {
        StabilityAnalysis analysis(settings.stability, settings.lu);
        PointAnalysisResult r;
        const auto t0 = std::chrono::steady_clock::now();
        const Status st = analysis.analyse(*problem, u, r);
        spectrum_s.push_back(since(t0));
        if (!st.is_ok()) throw std::runtime_error("the spectrum failed: " + st.message());
      }
      {
        const auto t0 = std::chrono::steady_clock::now();
        const Status st = NormalForms(settings.lu).hopf(*problem, p, u, omega, &guess, nf);
        form_s.push_back(since(t0));
        if (!st.is_ok()) throw std::runtime_error("the normal form failed: " + st.message());
        form_factor_s.push_back(nf.factor_seconds);
        form_derivative_s.push_back(nf.derivative_seconds);
      }
      {
        const auto t0 = std::chrono::steady_clock::now();
        const Status st = NormalForms(settings.lu, false, 0).hopf(*problem, p, u, omega, &guess, direct);
        direct_s.push_back(since(t0));
        if (!st.is_ok()) throw std::runtime_error("the normal form (direct solves) failed: " + st.message());
      }
    }
    const double spectrum = median(spectrum_s), factor = median(factor_s), form = median(form_s);
    fmt::print("{}\n", nf.summary());
    fmt::print("medians of {} runs:\n", repeat);
    fmt::print("  spectrum (its own factorisation of J)   {:8.3f} s\n", spectrum);
    fmt::print("  J's factorisation alone                 {:8.3f} s\n", factor);
    fmt::print("  spectrum without J's factorisation      {:8.3f} s\n", spectrum - factor);
    const double ff = median(form_factor_s), fd = median(form_derivative_s);
    fmt::print("  normal form                             {:8.3f} s\n", form);
    fmt::print("    {} factorisations                     {:8.3f} s\n", nf.factorisations, ff);
    fmt::print("    {} derivative evaluations            {:8.3f} s\n", nf.derivative_evaluations, fd);
    fmt::print("    the rest ({} GMRES iterations, ...)   {:8.3f} s\n", nf.gmres_iterations, form - ff - fd);
    fmt::print(
        "  normal form, every solve on a factorisation of its own {:.3f} s ({} factorisations; l1 {:.3e} "
        "relative from the above)\n",
        median(direct_s), direct.factorisations, std::abs(direct.l1 - nf.l1) / std::abs(direct.l1));
    fmt::print("  normal form / spectrum                  {:8.2f}\n", form / spectrum);
    fmt::print("  normal form / spectrum without J's LU   {:8.2f}\n", form / (spectrum - factor));
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_normal_form: {}\n", e.what());
    return 1;
  }
  return 0;
}
