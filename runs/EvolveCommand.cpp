#include "runs/EvolveCommand.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "continuation/output/BranchFile.hpp"
#include "continuation/output/TimeSeriesFile.hpp"
#include "continuation/start/StartSolver.hpp"
#include "continuation/time/TimeIntegrator.hpp"
#include "core/SolutionWriter.hpp"
#include "runs/BranchOutput.hpp"
#include "runs/CommandRun.hpp"
#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/OutputFile.hpp"
#include "runs/RunHooks.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/StoredStart.hpp"
#include "stability/EigenSolver.hpp"

namespace keller {

namespace {

// What a run perturbs its start with, and how.
struct PerturbationOptions {
  std::string kind = "none";  // none, computed, stored
  double amplitude = 1e-4;    // the perturbation's largest entry over max(|u_start|_inf, 1)
  double shift_re = 0.0, shift_im = 0.0;
  int eigenvalues = 6;
  int save_every = 10, print_every = 10;
};

PerturbationOptions perturbation_options_from(const Scene& scene) {
  PerturbationOptions o;
  o.kind = scene.string("evolve.perturbation");
  o.amplitude = scene.real("evolve.amplitude");
  o.shift_re = scene.real("evolve.shift_re");
  o.shift_im = scene.real("evolve.shift_im");
  o.eigenvalues = scene.integer("evolve.eigenvalues");
  o.save_every = scene.integer("evolve.save_every");
  o.print_every = scene.integer("evolve.print_every");
  return o;
}

// The state the run starts from (the steady state it is perturbed from: deviations are measured
// from it) and the mode it is perturbed along.
struct Reference {
  Vector state;
  std::optional<StoredMode> mode;
  Vector differential;  // 1 for the unknowns with a time derivative (B's nonzero columns at the state)
};

// The deviation from the reference, and with a mode its components along Re phi and Im phi (least
// squares: d ~ a Re phi + b Im phi, so that z = a - i b evolves as exp(-sigma t) in the linear regime)
// over the differential unknowns: BDF2's values of algebraic unknowns of index above one (the
// solid's pressure when the wall has inertia) need not follow the mode.
TimeColumns reference_columns(const Reference& ref) {
  TimeColumns c;
  c.names = {"deviation"};
  if (ref.mode) c.names.insert(c.names.end(), {"mode_re", "mode_im", "mode_amplitude"});
  c.values = [&ref](const Vector& u) {
    Vector d = u - ref.state;
    std::vector<double> v = {d.lpNorm<Eigen::Infinity>()};
    if (!ref.mode) return v;
    Vector p = ref.mode->re, q = ref.mode->im;
    if (ref.differential.size() == d.size()) {
      d = d.cwiseProduct(ref.differential);
      p = p.cwiseProduct(ref.differential);
      q = q.cwiseProduct(ref.differential);
    }
    const double pp = p.squaredNorm(), pq = p.dot(q), qq = q.squaredNorm(), pd = p.dot(d), qd = q.dot(d);
    const double det = pp * qq - pq * pq;
    double a = pp > 0.0 ? pd / pp : 0.0, b = 0.0;
    if (qq > 0.0 && det > 1e-12 * pp * qq) {  // a real mode (Im phi = 0 or parallel to Re phi): a alone
      a = (qq * pd - pq * qd) / det;
      b = (pp * qd - pq * pd) / det;
    }
    v.insert(v.end(), {a, b, std::hypot(a, b)});
    return v;
  };
  return c;
}

void write_reference(H5File& f, const Reference& ref) {
  f.write_vector("/evolve_start/state", std::vector<double>(ref.state.data(), ref.state.data() + ref.state.size()));
  if (!ref.mode) return;
  const long n = ref.state.size();
  std::vector<double> m(ref.mode->re.data(), ref.mode->re.data() + n);
  m.insert(m.end(), ref.mode->im.data(), ref.mode->im.data() + n);
  f.write_matrix("/evolve_start/mode", m.data(), 2, n);
  f.set_attribute("/evolve_start/mode", "sigma_re", ref.mode->sigma_re);
  f.set_attribute("/evolve_start/mode", "sigma_im", ref.mode->sigma_im);
}

Reference read_reference(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  Reference ref;
  long r = 0, c = 0;
  const std::vector<double> s = f.read_matrix("/evolve_start/state", &r, &c);
  ref.state = Eigen::Map<const Vector>(s.data(), static_cast<long>(s.size()));
  if (f.exists("/evolve_start/mode")) {
    const std::vector<double> m = f.read_matrix("/evolve_start/mode", &r, &c);
    StoredMode mode;
    mode.re = Eigen::Map<const Vector>(m.data(), c);
    mode.im = Eigen::Map<const Vector>(m.data() + c, c);
    mode.sigma_re = f.read_double_attribute("/evolve_start/mode", "sigma_re");
    mode.sigma_im = f.read_double_attribute("/evolve_start/mode", "sigma_im");
    ref.mode = mode;
  }
  return ref;
}

// The eigenvector of the most unstable eigenvalue (smallest Re sigma) among those nearest the
// shift, at the state u.
Status computed_mode(Problem& problem, const Vector& u, const PerturbationOptions& o, const SparseLUOptions& lu,
                     StoredMode& mode) {
  SparseMatrix J = problem.jacobian_pattern(), B;
  Vector F;
  Status st = problem.jacobian(u, F, J);
  if (st.is_ok()) st = problem.mass_matrix(u, B);
  if (!st.is_ok()) return st;
  EigenOptions eo;
  eo.count = std::min(o.eigenvalues, static_cast<int>(u.size()) - 2);
  eo.shift = {o.shift_re, o.shift_im};
  eo.vectors = true;
  EigenSolver solver(lu);
  EigenResult res;
  st = solver.solve(J, B, eo, res);
  if (res.pairs.empty()) return st.is_ok() ? Status{StatusCode::NotConverged, "no finite eigenvalue"} : st;
  const EigenPair& p = res.pairs.front();  // ordered by Re sigma ascending: the most unstable first
  mode.re = p.vector.real();
  mode.im = p.vector.imag();
  mode.sigma_re = p.value.real();
  mode.sigma_im = p.value.imag();
  return {};
}

// One line every N steps, and every rejection.
class TimePrinter final : public TimeObserver {
 public:
  TimePrinter(int every, const TimeColumns& columns) : every_(std::max(every, 1)), columns_(columns) {}
  void on_step(const TimePoint& p) override {
    if (p.step % every_ != 0) return;
    const std::vector<double> v = columns_.values(p.u);
    std::string extra;
    for (size_t i = 0; i < v.size(); ++i) extra += fmt::format("  {} {:.4e}", columns_.names[i], v[i]);
    fmt::print("step {:>6}  t = {:<13.6e} h = {:<10.3e} error {:<8.3g} it {:>2}  f {:>1}  r {:>1}{}  {:.1f} s\n",
               p.step, p.t, p.h, p.error, p.iterations, p.factorisations, p.rejected, extra, p.seconds);
    std::fflush(stdout);
  }
  void on_rejected(double t, double h, const std::string& why) override {
    fmt::print("  rejected the step to t = {:.6e} (h = {:.3e}): {}\n", t, h, why);
  }

 private:
  int every_;
  const TimeColumns& columns_;
};

class TimeObservers final : public TimeObserver {
 public:
  explicit TimeObservers(std::vector<TimeObserver*> list) : list_(std::move(list)) {}
  void on_step(const TimePoint& p) override {
    for (auto* o : list_) o->on_step(p);
  }
  void on_rejected(double t, double h, const std::string& why) override {
    for (auto* o : list_) o->on_rejected(t, h, why);
  }
  void on_finish(const std::string& reason, const TimePoint& last) override {
    for (auto* o : list_) o->on_finish(reason, last);
  }

 private:
  std::vector<TimeObserver*> list_;
};

const RunFileKind kTimeSeries{"time series",       "time-series file", "steps",  "step",
                              "/evolve/exit_code", "before t_end",     "evolved"};

// The options of a run, as its scene sets them ([evolve], [newton], [linear_solver], [start]).
struct EvolveSettings {
  TimeOptions time;
  PerturbationOptions perturbation;
  NewtonOptions newton;
  SparseLUOptions lu;
  StartOptions start;
};

// What the run starts from, read before anything is computed: what an earlier run of this command
// left in OUT.h5.part (its unfinished steps, continued, with the reference they were measured from),
// or the point of --restart (with its stored eigenvector where the perturbation is "stored").
struct EvolveSource {
  LeftRun left;
  std::optional<TimeSeed> seed;
  Reference reference;
  std::vector<std::string> warnings;  // the refusals --force let through
};

EvolveSource read_evolve_source(const CommandRun& run, const std::string& record, bool fresh,
                                const std::optional<StoredStart>& from, const PerturbationOptions& perturbation,
                                Problem& problem) {
  EvolveSource source;
  source.left = run.left(record, fresh, [](const std::string& path) {
    const TimeTable t = read_time_table(path);
    return std::pair<long, std::string>(t.rows.rows(), t.status);
  });
  if (source.left.kind == LeftRun::Kind::unfinished) source.seed = read_time_seed(run.work());
  if (source.left.kind != LeftRun::Kind::none) {
    source.reference = read_reference(run.work());
  } else if (from) {
    const std::string parameter = read_branch_table(from->file).parameter;
    const StoredPoint stored = read_stored_start(*from, run.loaded(), problem, parameter, source.warnings);
    for (const Parameter& q : problem.parameters().list())
      if (const auto v = stored.value_of(q.name)) problem.parameters().set(q.name, *v);
    source.reference.state = stored.point.u;
    if (perturbation.kind == "stored") {
      source.reference.mode = read_branch_mode(from->file, stored.point.index);
      if (!source.reference.mode)
        throw std::invalid_argument(fmt::format(
            "--restart '{}': row {} has no stored eigenvector (trace with [stability] enabled = true; rows with a "
            "stored solution keep theirs); perturbation = \"computed\" computes one",
            from->file, stored.point.index));
    }
    fmt::print("starting from row {} of {} ({} = {:.10g})\n", stored.point.index, from->file, parameter,
               stored.point.lambda);
  }
  return source;
}

// The steady state the run starts from at the scene's parameter values (StartSolver). Throws
// CommandFailure (exit 1, nothing written) where it fails.
Vector steady_state(Problem& problem, const EvolveSettings& settings) {
  StartSolver start_solver(problem, settings.newton, settings.lu, settings.start,
                           [](const std::string& line) { fmt::print("{}\n", line); });
  Vector u = problem.initial_guess();
  fmt::print("steady state to start from\n");
  print_newton_header();
  const StartResult r = start_solver.solve(u, print_newton_row);
  if (!r.status.is_ok()) throw CommandFailure::numerical("the steady state failed", r.status);
  fmt::print("steady state: {}, {} Newton iterations\n", r.path, r.newton_iterations);
  return u;
}

// 1 for the unknowns with a time derivative at `state` (B's nonzero columns; a problem without a
// time-dependent form was refused when it was built). Throws CommandFailure: exit 1 where B fails there.
Vector differential_unknowns(Problem& problem, const Vector& state) {
  SparseMatrix B;
  const Status st = problem.mass_matrix(state, B);
  if (!st.is_ok()) throw CommandFailure(exit_code::numerical_failure, "the mass matrix at the start: " + st.describe());
  if (B.nonZeros() == 0 || B.coeffs().cwiseAbs().maxCoeff() == 0.0)
    fmt::print("note: B = 0 (no row carries a time derivative): every step is the steady state\n");
  Vector differential = Vector::Zero(state.size());
  for (int k = 0; k < B.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(B, k); it; ++it)
      if (it.value() != 0.0) differential[it.col()] = 1.0;
  return differential;
}

// The start perturbed along the mode's real part, its largest entry `amplitude` max(|state|_inf, 1).
Vector perturbed(const Reference& ref, double amplitude) {
  Vector u0 = ref.state;
  if (!ref.mode) return u0;
  const double biggest = ref.mode->re.lpNorm<Eigen::Infinity>();
  if (!(biggest > 0.0)) throw CommandFailure(exit_code::numerical_failure, "the eigenvector's real part is zero");
  u0 += (amplitude * std::max(ref.state.lpNorm<Eigen::Infinity>(), 1.0) / biggest) * ref.mode->re;
  return u0;
}

// Where the run starts: the steady state it was given (continued or --restart) or solves now, the
// unknowns with a time derivative there and, for a new run, the mode it is perturbed along (stored,
// or computed now). Returns the first state: the steady state perturbed along the mode, or for a
// continued run (whose steps hold its state) the steady state. Throws CommandFailure.
Vector first_state(Problem& problem, const EvolveSettings& settings, EvolveSource& source, bool restarted) {
  const bool continued = source.seed.has_value();
  Reference& ref = source.reference;
  if (!continued && !restarted) ref.state = steady_state(problem, settings);
  ref.differential = differential_unknowns(problem, ref.state);
  if (!continued && settings.perturbation.kind == "computed") {
    StoredMode mode;
    const Status st = computed_mode(problem, ref.state, settings.perturbation, settings.lu, mode);
    if (!st.is_ok() && mode.re.size() == 0) throw CommandFailure::numerical("no eigenvector to perturb along", st);
    ref.mode = mode;
  }
  if (ref.mode)
    fmt::print("perturbation along the eigenvector of sigma = {:.10g} {:+.10g} i (growth rate {:.10g}), amplitude {}\n",
               ref.mode->sigma_re, ref.mode->sigma_im, -ref.mode->sigma_re, settings.perturbation.amplitude);
  return continued ? ref.state : perturbed(ref, settings.perturbation.amplitude);
}

// What the time-series file holds before its steps: the run's header and record (`restart`: the
// --restart it started from, or empty), the state and mode it is measured from, the mesh.
std::function<void(H5File&)> series_header(const CommandRun& run, Problem& problem, const std::string& record,
                                           const Reference& ref, const std::string& restart) {
  return [&run, &problem, record, &ref, restart](H5File& f) {
    write_run_header(f, run.loaded(), problem);
    f.write_string("/problem/run", record);
    if (!restart.empty()) f.set_attribute("/problem", "restarted_from", restart);
    write_reference(f, ref);
    const SolutionFields sf = problem.fields(ref.state);
    if (sf.mesh) write_mesh(f, "/mesh", *sf.mesh);
  };
}

// What the run reports: its cost on the terminal, and in `summary`.
void report_time_run(const TimeResult& result, long unknowns, RunSummary& summary) {
  fmt::print("{} steps, {} rejected, {} factorisations ({:.2f} per step), {} Newton iterations, {:.2f} s; {}\n",
             result.steps, result.rejected, result.factorisations,
             result.steps > 0 ? static_cast<double>(result.factorisations) / result.steps : 0.0,
             result.newton_iterations, result.seconds, result.reason);
  summary.reason = result.reason;
  summary.unknowns = unknowns;
  summary.points = result.steps;
  summary.rejected = result.rejected;
  summary.factorisations = result.factorisations;
  summary.seconds = result.seconds;
}

}  // namespace

void declare_evolve_keys(SceneSchema& s) {
  TimeOptions::declare(s);
  const PerturbationOptions d;
  s.string("evolve.perturbation", d.kind,
           "perturb the start along an eigenvector of J phi = sigma B phi: computed at the start (the most unstable "
           "of those nearest the shift) or stored with the --restart row (keller trace with [stability])",
           {"none", "computed", "stored"});
  s.real("evolve.amplitude", d.amplitude,
         "the perturbation's largest entry, relative to max(|u_start|_inf, 1) (small: the linear regime)",
         Range::positive());
  s.real("evolve.shift_re", d.shift_re, "perturbation = computed: real part of the shift the eigenvalues are nearest");
  s.real("evolve.shift_im", d.shift_im,
         "perturbation = computed: imaginary part of the shift (near the frequency of a Hopf pair)");
  s.integer("evolve.eigenvalues", d.eigenvalues,
            "perturbation = computed: eigenvalues computed nearest the shift (the most unstable is taken)",
            Range::at_least(1));
  s.integer("evolve.save_every", d.save_every, "store the state of every N-th step (with the start and the end)",
            Range::at_least(1));
  s.integer("evolve.print_every", d.print_every, "a progress line every N-th step", Range::at_least(1));
}

int run_evolve(const EvolveArguments& args, RunSummary* out_summary) {
  return run_command(out_summary, [&](RunSummary& summary) {
    CommandRun run(summary, kTimeSeries);
    // 1. the scene, its options and the files of the run: nothing is written before all are right
    EvolveSettings settings;
    run.load(args.scene, args.output, declare_evolve_keys, args.overrides, [&](const Scene& scene) {
      settings = {TimeOptions::from_scene(scene), perturbation_options_from(scene), newton_options_from(scene),
                  sparse_lu_options_from(scene), StartOptions::from_scene(scene)};
      if (settings.perturbation.kind == "stored" && args.restart.empty())
        throw scene.error("evolve.perturbation",
                          "'stored' takes the eigenvector stored with the --restart row; there is no --restart");
    });
    std::optional<StoredStart> from;
    run.check([&](RunFiles& files) {
      if (args.force && args.restart.empty()) throw std::invalid_argument("--force applies to a start from --restart");
      if (!args.restart.empty()) {
        from = parse_stored_start("--restart", args.restart);
        from->force = args.force;
        files.input("--restart file", from->file);
      }
      declare_run_outputs(files, run.out(), kTimeSeries.file, run.with_fields());
    });
    Problem& problem = run.build([](Problem& p) {
      if (const std::string why = time_form_refusal(p); !why.empty())
        throw std::invalid_argument(why + ": there is nothing to integrate in time");
    });

    // 2. where the run starts: an unfinished run of this command, a stored point, or a steady state
    const std::string record =
        run.scene().canonical_values() + fmt::format("start = {}\n", from ? "restart " + args.restart : "steady state");
    EvolveSource source;
    checking([&] { source = read_evolve_source(run, record, args.fresh, from, settings.perturbation, problem); });
    for (const std::string& w : source.warnings) fmt::print(stderr, "keller: warning: {}\n", w);
    fmt::print("problem: {}\n", problem.summary());
    if (source.left.kind != LeftRun::Kind::none) {  // the parameters it used: the scene's, or its stored start's
      H5File f(run.work(), H5File::Mode::Read);
      for (const auto& [name, value] : read_run_header(f).parameters)
        if (problem.parameters().has(name)) problem.parameters().set(name, value);
    }
    const auto fields = [&problem](const Vector& u) { return problem.fields(u); };
    summary.unknowns = problem.size();
    if (source.left.kind == LeftRun::Kind::ended)
      return run.publish_left(source.left, series_fields(fields, &InterruptGuard::requested));
    const std::optional<TimeSeed>& seed = source.seed;
    const Reference& ref = source.reference;
    const Vector u0 = first_state(problem, settings, source, from.has_value());

    // 3. the run, written to OUT.h5.part step by step
    const TimeColumns columns = reference_columns(ref);
    TimeIntegrator integrator(problem, settings.time, settings.newton, settings.lu);
    if (ref.mode) integrator.set_error_reference(ref.state);
    TimeResult result;
    const RunEnd end = run.write<TimeSeriesFile>(
        [&] {
          return std::make_unique<TimeSeriesFile>(run.work(), problem, columns, settings.perturbation.save_every,
                                                  series_header(run, problem, record, ref, from ? args.restart : ""),
                                                  seed ? &*seed : nullptr);
        },
        [&](TimeSeriesFile& file) {
          TimePrinter printer(settings.perturbation.print_every, columns);
          const std::unique_ptr<TimeObserver> hook = time_hook(problem);
          TimeObservers observers(hook ? std::vector<TimeObserver*>{&file, &printer, hook.get()}
                                       : std::vector<TimeObserver*>{&file, &printer});
          const auto stop = [] { return InterruptGuard::requested(); };
          if (seed) {
            fmt::print("continuing the unfinished run in {} from its step {} (t = {:.10g}; --fresh starts over)\n",
                       run.work(), seed->step(), seed->history.back.front().t);
            result = integrator.resume(seed->history, observers, stop);
          } else {
            result = integrator.run(u0, 0.0, observers, stop);
          }
          return RunEnd{result.code == TimeStop::Interrupted, result.code == TimeStop::StepFloor};
        });
    report_time_run(result, problem.size(), summary);

    // 4. the file takes its name: an interrupted run stays where it is, to be continued; a failed one
    // never replaces an existing file
    return run.publish(end, series_fields(fields, &InterruptGuard::requested));
  });
}

}  // namespace keller
