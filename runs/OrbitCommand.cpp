#include "runs/OrbitCommand.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>

#include "continuation/orbits/OrbitContinuation.hpp"
#include "continuation/output/BranchFile.hpp"
#include "continuation/output/ContinuedBranch.hpp"
#include "continuation/output/ProgressPrinter.hpp"
#include "core/Newton.hpp"
#include "core/SolutionWriter.hpp"
#include "runs/CommandRun.hpp"
#include "runs/EvolveStart.hpp"
#include "runs/FloquetAnalysis.hpp"
#include "runs/Interrupts.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/StoredStart.hpp"
#include "runs/TraceStart.hpp"
#include "stability/NormalForms.hpp"

namespace keller {

const char* const kOrbitStabilityRefusal =
    "[stability] analyses steady states; an orbit branch has its Floquet multipliers ([orbit] multipliers)";

namespace {

constexpr double kProgressSeconds = 10.0;

const RunFileKind kOrbitBranch{"orbit branch",      "branch file",      "rows",  "orbit",
                               "/branch/exit_code", "before its range", "traced"};

// The problem as the branch file sees an orbit branch: its unknowns are u0's, its observables the
// orbit's (OrbitContinuation::observable_names).
class OrbitView final : public Problem {
 public:
  OrbitView(Problem& inner, std::vector<std::string> observables)
      : inner_(inner), observables_(std::move(observables)) {}
  std::string name() const override { return inner_.name(); }
  int size() const override { return inner_.size(); }
  ParameterSet& parameters() override { return inner_.parameters(); }
  const ParameterSet& parameters() const override { return inner_.parameters(); }
  const SparseMatrix& jacobian_pattern() const override { return inner_.jacobian_pattern(); }
  Status residual(const Vector& u, Vector& F) override { return inner_.residual(u, F); }
  Vector initial_guess() override { return inner_.initial_guess(); }
  std::vector<std::string> observable_names() const override { return observables_; }
  SolutionFields fields(const Vector& u) const override { return inner_.fields(u); }

 private:
  Problem& inner_;
  std::vector<std::string> observables_;
};

// --orbit's flags against the others; the stored Hopf point's file (or the evolve run's) is
// declared as an input. An evolve run gives an empty file name.
StoredStart checked_orbit_start(const TraceArguments& args, const TraceSettings& settings, RunFiles& files,
                                const CommandRun& run) {
  if (args.from.empty() == args.switch_at.empty())
    throw std::invalid_argument(
        "--orbit starts at a located Hopf point (--from FILE.h5:ROW, or hopf1), from the last state of a "
        "keller evolve run on a limit cycle (--from RUN.h5), or at a period doubling of an orbit branch onto the "
        "doubled branch (--switch ORBITS.h5:ROW, or pd1): one of them");
  if (!args.curve.empty() || !args.restart.empty() || !args.free.empty())
    throw std::invalid_argument("--orbit excludes --curve, --free and --restart");
  if (settings.stability.enabled) throw std::invalid_argument(kOrbitStabilityRefusal);
  if (!args.switch_at.empty()) {
    StoredStart at = parse_stored_start("--switch", args.switch_at);
    at.located = PointKind::PeriodDoubling;
    at.orbit = true;
    at.force = args.force;
    files.input("--switch file", at.file);
    declare_run_outputs(files, run.out(), kOrbitBranch.file, run.with_fields());
    return at;
  }
  if (is_time_series(args.from)) {  // an evolve run: read in run_orbit_trace
    files.input("--from file", args.from);
    declare_run_outputs(files, run.out(), kOrbitBranch.file, run.with_fields());
    return {};
  }
  StoredStart from = parse_stored_start("--from", args.from);
  from.located = PointKind::Hopf;
  from.orbit = true;
  from.curve = false;  // the orbits continue in the Hopf point's own parameter (or another one the scene names)
  from.force = args.force;
  files.input("--from file", from.file);
  declare_run_outputs(files, run.out(), kOrbitBranch.file, run.with_fields());
  return from;
}

// Whether B(u) has a nonzero entry at the parameters' present values.
bool has_time_derivative(Problem& problem, const Vector& u) {
  SparseMatrix B;
  if (!problem.mass_matrix(u, B).is_ok()) return false;
  for (Eigen::Index k = 0; k < B.nonZeros(); ++k)
    if (B.valuePtr()[k] != 0.0) return true;
  return false;
}

// A steady state at the parameter's present value, by Newton from `guess`.
Vector steady_state(Problem& problem, int p, const Vector& guess, const TraceSettings& settings) {
  Vector u = guess;
  NewtonSolver newton(problem, settings.newton, settings.lu);
  const NewtonResult r = newton.solve(u);
  if (!r.converged())
    throw CommandFailure::numerical(fmt::format("the steady state at {} = {:.10g}, from the Hopf point",
                                                problem.parameters().info(p).name, problem.parameters().value(p)),
                                    r.status);
  return u;
}

struct OrbitStart {
  OrbitPoint first, second;
  NormalForm nf;
};

// The first two orbits near the Hopf point of `stored`: at lambda_H + side d and + 2 side d, each
// from the normal form's orbit u = u_s + 2 |z| Re(q e^(i omega t)), |z|^2 = -g' (lambda - lambda_H) /
// Re c1, on the steady state u_s there, corrected at fixed lambda.
OrbitStart orbit_start(Problem& problem, int p, const StoredStart& from, const StoredPoint& stored,
                       const TraceSettings& settings, const OrbitContinuationOptions& options,
                       OrbitContinuation& continuation) {
  const BranchPoint& hopf = stored.point;
  OrbitStart s;
  std::optional<StoredMode> mode;
  checking([&] { mode = read_branch_mode(from.file, hopf.index); });
  if (!mode || mode->re.size() != hopf.u.size())
    throw CommandFailure::bad_input(
        fmt::format("{}: row {} holds no critical eigenvector (a Hopf point located by [stability] has one)", from.file,
                    hopf.index));
  const Eigen::VectorXcd guess = mode->re.cast<std::complex<double>>() + std::complex<double>(0.0, 1.0) * mode->im;
  problem.parameters().set(p, hopf.lambda);
  const Status st = NormalForms(settings.lu).hopf(problem, p, hopf.u, std::abs(mode->sigma_im), &guess, s.nf);
  if (!st.is_ok()) throw CommandFailure::numerical("the Hopf point's normal form", st);
  const double re_c1 = s.nf.l1 * s.nf.omega;
  if (!(s.nf.side != 0) || !(re_c1 != 0.0))
    throw CommandFailure::numerical("the Hopf point's normal form",
                                    {StatusCode::InvalidState, "l1 = 0 (degenerate): it predicts no orbit"});
  fmt::print("{}\n", s.nf.summary());
  const double d = options.start_distance > 0.0 ? options.start_distance : 1e-2 * std::max(std::abs(hopf.lambda), 1.0);
  Vector u_s = hopf.u;
  for (int k = 1; k <= 2; ++k) {
    const double lambda = hopf.lambda + s.nf.side * k * d;
    problem.parameters().set(p, lambda);
    u_s = steady_state(problem, p, u_s, settings);
    const double z = std::sqrt(-s.nf.growth_rate_derivative * (lambda - hopf.lambda) / re_c1);
    const Vector u0 = u_s + 2.0 * z * s.nf.q.real();
    const Vector flow = -2.0 * z * s.nf.omega * s.nf.q.imag();
    OrbitPoint& o = k == 1 ? s.first : s.second;
    // the second from the first, moved by the change of the steady state and the amplitude's growth
    const Status c = k == 1 ? continuation.converge(u0, s.nf.period, flow, o)
                            : continuation.converge(s.first.u0, s.first.period, s.first.flow, o);
    if (!c.is_ok())
      throw CommandFailure::numerical(
          fmt::format("the orbit at {} = {:.10g} near the Hopf point", problem.parameters().info(p).name, lambda), c);
    fmt::print("orbit at {} = {:.10g}: period {:.10g} (2 pi / omega = {:.10g}), {} Newton iterations\n",
               problem.parameters().info(p).name, lambda, o.period, s.nf.period, o.iterations);
  }
  return s;
}

// The doubled branch from the period doubling `stored` of an orbit branch: the stored orbit
// corrected again at its parameter value (on a grid recorded from it), the eigenvector of its
// multiplier nearest -1, and the first two orbits of the doubled branch, twice the period, the second
// `continuation.initial_step` (arclength) from the first along that eigenvector
// (OrbitContinuation::switch_period_doubling). Either side gives the same branch, half a doubled
// period apart.
OrbitStart doubling_start(Problem& problem, int p, const StoredStart& at, const StoredPoint& stored,
                          const OrbitContinuationOptions& options, OrbitContinuation& continuation) {
  const BranchPoint& pd = stored.point;
  const std::string& name = problem.parameters().info(p).name;
  double period = 0.0;
  checking([&] { period = stored.table.rows(pd.index, stored.table.column("period")); });
  problem.parameters().set(p, pd.lambda);
  OrbitStart s;
  OrbitPoint orbit;
  Status st = continuation.converge(pd.u, period, {}, orbit);
  if (!st.is_ok())
    throw CommandFailure::numerical(fmt::format("the period doubling's orbit of row {} of {}", pd.index, at.file), st);
  Vector v;
  if (!(st = continuation.period_doubling_vector(orbit, v)).is_ok())
    throw CommandFailure::numerical(
        fmt::format("the period doubling of row {} of {}: its multiplier near -1", pd.index, at.file), st);
  if (!(st = continuation.switch_period_doubling(orbit, v, options.step, s.first, s.second)).is_ok())
    throw CommandFailure::numerical(fmt::format("the doubled branch's first orbit from row {} of {} ({} = {:.10g})",
                                                pd.index, at.file, name, pd.lambda),
                                    st);
  fmt::print("period doubling at {} = {:.10g} (period {:.10g}); the doubled orbit at {} = {:.10g}: period {:.10g}\n",
             name, orbit.lambda, orbit.period, name, s.second.lambda, s.second.period);
  return s;
}

// The orbit through the last state of an evolve run at its parameter value, and the one at
// `orbit.start_distance` (0: 1e-2 max(|lambda|, 1)) from it in `continuation.direction`: the
// secant the run continues along.
OrbitStart evolve_start(Problem& problem, int p, const EvolveStart& e, const OrbitContinuationOptions& options,
                        int direction, OrbitContinuation& continuation, const std::string& file) {
  OrbitStart s;
  const std::string& name = problem.parameters().info(p).name;
  fmt::print("{}: the last state (t = {:.10g}); period {:.10g} from the crossings of {}\n", file, e.t, e.period,
             e.observable);
  const double d = options.start_distance > 0.0 ? options.start_distance : 1e-2 * std::max(std::abs(e.parameter), 1.0);
  for (int k = 0; k < 2; ++k) {
    const double lambda = e.parameter + k * direction * d;
    problem.parameters().set(p, lambda);
    OrbitPoint& o = k == 0 ? s.first : s.second;
    const Status c = k == 0 ? continuation.converge(e.u, e.period, {}, o)
                            : continuation.converge(s.first.u0, s.first.period, s.first.flow, o);
    if (!c.is_ok())
      throw CommandFailure::numerical(fmt::format("the orbit at {} = {:.10g} from {}", name, lambda, file), c);
    fmt::print("orbit at {} = {:.10g}: period {:.10g}, {} Newton iterations\n", name, lambda, o.period, o.iterations);
  }
  return s;
}

// The last two rows of an unfinished orbit branch (every row stores its u0), each corrected again
// at its parameter value: the secant the run continues along. The norm's scales are the first
// run's: the file's state scale and the first row's period.
OrbitStart continued_start(Problem& problem, int p, const Unfinished& unfinished, OrbitContinuation& continuation) {
  const BranchSeed& seed = unfinished.seed;
  const long stored = seed.saved.rows();
  if (stored < 2 || seed.solutions.rows() < stored)
    throw CommandFailure::bad_input(
        fmt::format("{}: fewer than two stored orbits to continue from; run again with --fresh", unfinished.file));
  const auto column = [&](const std::string& name) {
    for (size_t i = 0; i < seed.columns.size(); ++i)
      if (seed.columns[i] == name) return static_cast<long>(i);
    throw CommandFailure::bad_input(fmt::format("{}: no column '{}': not an orbit branch", unfinished.file, name));
  };
  const long period = column("period");
  continuation.set_scales(unfinished.state_scale, seed.table(0, period));
  OrbitStart s;
  for (int k = 0; k < 2; ++k) {
    const long slot = stored - 2 + k;
    const int row = static_cast<int>(seed.saved(slot, 0));
    const double lambda = seed.saved(slot, 2);
    problem.parameters().set(p, lambda);
    OrbitPoint& o = k == 0 ? s.first : s.second;
    const Status st = continuation.converge(seed.solutions.row(slot).transpose(), seed.table(row, period), {}, o);
    if (!st.is_ok())
      throw CommandFailure::numerical(fmt::format("the stored orbit of row {} of {}", row, unfinished.file), st);
    o.s = seed.saved(slot, 5);
  }
  say_continuing("orbit branch", unfinished, problem.parameters().info(p).name);
  return s;
}

}  // namespace

int run_orbit_trace(const TraceArguments& args, RunSummary* out_summary) {
  return run_command(out_summary, [&](RunSummary& summary) {
    CommandRun run(summary, kOrbitBranch);
    TraceSettings settings;
    OrbitContinuationOptions options;
    run.load(args.scene, args.output, declare_trace_keys, args.overrides, [&](const Scene& scene) {
      settings = TraceSettings::from_scene(scene);
      options = OrbitContinuationOptions::from_scene(scene, settings.continuation);
    });
    // a correction's Newton iterations, at most one line per kProgressSeconds (the long ones only)
    const auto started = std::chrono::steady_clock::now();
    auto last_line = started;
    options.corrector.progress = [started, &last_line](int it, double residual, long krylov) {
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - last_line).count() < kProgressSeconds) return;
      last_line = now;
      fmt::print("  shooting Newton iteration {}: |Phi(u0) - u0| = {:.3e}, {} GMRES iterations so far ({:.0f} s)\n", it,
                 residual, krylov, std::chrono::duration<double>(now - started).count());
      std::fflush(stdout);
    };
    StoredStart from;
    run.check([&](RunFiles& files) { from = checked_orbit_start(args, settings, files, run); }, args.output_locked);
    const std::string& parameter = settings.continuation.parameter;
    Problem& problem = run.build([&](Problem& p) {
      if (!p.parameters().has(parameter))
        throw run.scene().error("continuation.parameter",
                                "unknown parameter '" + parameter + "'; this problem has: " + p.parameters().names());
      if (!has_time_form(p))
        throw run.scene().error("problem.type", "problem '" + p.name() +
                                                    "' has no time-dependent form (no mass matrix B): it has "
                                                    "no periodic orbits to trace");
    });
    const bool from_evolve = from.file.empty();
    TraceSource source;
    std::optional<EvolveStart> evolve;
    checking([&] {
      source = read_trace_source(run, trace_run_record(run.loaded(), args), args.fresh,
                                 from_evolve ? std::nullopt : std::optional<StoredStart>(from), problem, parameter);
      if (from_evolve && !source.unfinished && source.left.kind != LeftRun::Kind::ended)
        evolve = read_evolve_start(args.from, run.loaded(), problem, parameter, args.force, source.warnings);
    });
    for (const std::string& w : source.warnings) fmt::print(stderr, "keller: warning: {}\n", w);
    const int p = problem.parameters().index(parameter);
    FloquetAnalysis floquet = FloquetAnalysis::for_branch(options.multipliers);
    OrbitContinuation continuation(problem, p, options, &floquet);
    OrbitStart start;
    const std::optional<Unfinished>& unfinished = source.unfinished;
    if (unfinished) {
      start = continued_start(problem, p, *unfinished, continuation);
    } else if (evolve) {
      fmt::print("problem: {}\n", problem.summary());
      start = evolve_start(problem, p, *evolve, options, settings.continuation.direction, continuation, args.from);
      continuation.set_scales(start.first);
    } else if (from.switching) {
      use_stored_parameters(problem, *source.stored);
      fmt::print("problem: {}\n", problem.summary());
      start = doubling_start(problem, p, from, *source.stored, options, continuation);
    } else {
      const StoredPoint& stored = *source.stored;
      use_stored_parameters(problem, stored);
      problem.parameters().set(p, stored.point.lambda);
      if (const std::string why = time_form_refusal(problem, stored.point.u); !why.empty())
        throw CommandFailure::bad_input(fmt::format("{}: {}", args.from, why));
      if (!has_time_derivative(problem, stored.point.u))
        throw CommandFailure::bad_input(fmt::format(
            "{}: the mass matrix B is zero at the point's parameter values: this problem has no dynamics there "
            "and no periodic orbits",
            args.from));
      fmt::print("problem: {}\n", problem.summary());
      start = orbit_start(problem, p, from, stored, settings, options, continuation);
      continuation.set_scales(start.first);
    }
    problem.parameters().set(p, start.first.lambda);
    OrbitView view(problem, continuation.observable_names());
    OrbitContinuationResult result;
    const RunEnd end = run.write<BranchFile>(
        [&] {
          return std::make_unique<BranchFile>(
              run.work(), view, settings.continuation, std::vector<std::string>{}, continuation.state_scale(),
              [&](H5File& f) {
                write_run_header(f, run.loaded(), problem);
                f.write_string("/problem/run", trace_run_record(run.loaded(), args));
                const SolutionFields sf = problem.fields(start.first.u0);
                if (sf.mesh) write_mesh(f, "/mesh", *sf.mesh);
                if (args.switch_at.empty())
                  f.set_attribute("/problem", "orbit_from", args.from);
                else
                  f.set_attribute("/problem", "orbit_switch", args.switch_at);
              },
              continuation.analysis_columns(), unfinished ? &unfinished->seed : nullptr);
        },
        [&](BranchFile& file) {
          ProgressPrinter printer(parameter, 2);
          ObserverList observers({&file, &printer});
          std::optional<ContinuedBranch> continued;
          BranchObserver* observer = &observers;
          if (unfinished) observer = &continued.emplace(observers, unfinished->seed.row);
          result = continuation.run(start.first, start.second, *observer, &InterruptGuard::requested, !unfinished);
          return RunEnd{result.code == StopCode::Interrupted, is_failure(result.code)};
        });
    const ShootingMap::Counts& k = result.counts;
    fmt::print("{} orbits, {} rejected steps; {}\n", result.points, result.rejected, result.reason);
    fmt::print(
        "time {:.2f} s: forward periods {:.2f} ({} steps, {} Newton iterations in their solves), linearised passes "
        "{:.2f} ({}; of them multipliers {:.2f} s), {} Newton and {} GMRES iterations ({} inner, in the passes' "
        "solves), {} factorisations\n",
        result.seconds, k.forward_seconds, k.steps, k.newton_iterations, k.linearised_seconds, k.passes,
        result.multiplier_seconds, result.newton_iterations, result.krylov_iterations, k.inner_iterations,
        k.factorisations);
    summary.reason = result.reason;
    summary.unknowns = problem.size();
    summary.points = result.points;
    summary.rejected = result.rejected;
    summary.seconds = result.seconds;
    return run.publish(end, branch_fields(
                                xdmf_path_for(run.out()),
                                [&problem, p](const Vector& u, double lambda) {
                                  problem.parameters().set(p, lambda);
                                  return problem.fields(u);
                                },
                                &InterruptGuard::requested));
  });
}

}  // namespace keller
