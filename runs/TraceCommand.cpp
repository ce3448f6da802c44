#include "runs/TraceCommand.hpp"

#include <fmt/format.h>

#include <memory>
#include <optional>

#include "continuation/Continuation.hpp"
#include "continuation/curves/FoldCurveProblem.hpp"
#include "continuation/curves/HopfCurveProblem.hpp"
#include "continuation/orbits/OrbitContinuation.hpp"
#include "continuation/output/BranchFile.hpp"
#include "continuation/output/ContinuedBranch.hpp"
#include "continuation/output/ProgressPrinter.hpp"
#include "core/SolutionWriter.hpp"
#include "runs/BranchOutput.hpp"
#include "runs/CommandRun.hpp"
#include "runs/Interrupts.hpp"
#include "runs/NormalFormObserver.hpp"
#include "runs/OrbitCommand.hpp"
#include "runs/OutputFile.hpp"
#include "runs/RunHooks.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/StoredStart.hpp"
#include "runs/TraceStart.hpp"
#include "stability/StabilityAnalysis.hpp"

namespace keller {

void declare_trace_keys(SceneSchema& schema) {
  ContinuationOptions::declare(schema);
  StabilityOptions::declare(schema);
  OrbitContinuationOptions::declare(schema);
}

std::string trace_run_record(const LoadedScene& loaded, const TraceArguments& a) {
  std::string start = "steady state";
  if (!a.restart.empty()) start = "restart " + a.restart;
  if (!a.switch_at.empty()) start = fmt::format("switch {} {}", a.switch_at, a.switch_direction);
  if (!a.from.empty()) start = fmt::format("{} curve from {} in {}", a.curve, a.from, a.free);
  if (a.orbit)
    start = a.switch_at.empty() ? fmt::format("orbits from {}", a.from) : "doubled orbits from " + a.switch_at;
  return loaded.scene.canonical_values() + fmt::format("start = {}\n", start);
}

namespace {

const RunFileKind kBranch{"branch", "branch file", "rows", "point", "/branch/exit_code", "before its range", "traced"};

// The start the command line asks for (--restart, --switch or --from, each with its FILE.h5:ROW),
// its flags checked against each other and against the scene's `settings`; its file is declared
// before the run's own. Throws std::invalid_argument saying which flags do not go together.
std::optional<StoredStart> checked_start(const TraceArguments& args, const TraceSettings& settings, RunFiles& files,
                                         const CommandRun& run) {
  if (!args.restart.empty() && !args.switch_at.empty())
    throw std::invalid_argument("--restart and --switch exclude each other");
  if (args.force && args.restart.empty() && args.switch_at.empty() && args.from.empty())
    throw std::invalid_argument("--force applies to a start from --restart, --switch or --from");
  if (args.from.empty() != args.curve.empty())
    throw std::invalid_argument(
        "--from FILE.h5:ROW and --curve fold|hopf|event go together (a curve starts at a located point)");
  if (!args.free.empty() && args.from.empty())
    throw std::invalid_argument("--free applies to a curve (--from, --curve)");
  if (!args.curve.empty() && args.curve != "fold" && args.curve != "hopf" && args.curve != "event")
    throw std::invalid_argument("--curve: '" + args.curve + "' is not a curve keller traces (fold, hopf, event)");
  if (!args.from.empty() && (!args.restart.empty() || !args.switch_at.empty()))
    throw std::invalid_argument("--from excludes --restart and --switch");
  if (!args.from.empty() && settings.stability.enabled)
    throw std::invalid_argument(
        "[stability]: the points of a curve are not analysed; trace ordinary branches "
        "at the curve's parameter values for their stability");
  std::optional<StoredStart> from;
  if (!args.restart.empty()) from = parse_stored_start("--restart", args.restart);
  if (!args.switch_at.empty()) from = parse_stored_start("--switch", args.switch_at);
  if (!args.from.empty()) {
    from = parse_stored_start("--from", args.from);
    from->located = args.curve == "event" ? PointKind::Event : args.curve == "hopf" ? PointKind::Hopf : PointKind::Fold;
  }
  if (from) {
    from->force = args.force;
    files.input(from->flag + " file", from->file);
  }
  declare_run_outputs(files, run.out(), kBranch.file, run.with_fields());
  return from;
}

// Refuses (SceneError naming the key) a problem without the run's parameter, or too small for the
// spectrum [stability] asks for.
void refuse_problem(Problem& problem, const TraceSettings& settings, const Scene& scene) {
  const std::string& parameter = settings.continuation.parameter;
  if (!problem.parameters().has(parameter))
    throw scene.error("continuation.parameter",
                      "unknown parameter '" + parameter + "'; this problem has: " + problem.parameters().names());
  if (settings.stability.enabled) settings.stability.check_problem(scene, problem);
}

// The fields of a stored state of the traced problem at its parameter value `lambda` (parameter p): a
// curve's state holds the problem's unknowns and then the value of its second parameter (p1 >= 0).
FieldsAt fields_of(Problem& problem, int p, int p1) {
  return [&problem, p, p1](const Vector& u, double lambda) {
    problem.parameters().set(p, lambda);
    if (p1 >= 0) problem.parameters().set(p1, u[problem.size()]);
    return problem.fields(u.head(problem.size()));
  };
}

// The ended run of this command in OUT.h5.part, killed before it took its name: published now, at
// the parameter values it was traced at (a curve's second parameter from its --from branch).
int publish_left_branch(CommandRun& run, const std::optional<StoredStart>& from, const std::string& parameter,
                        const LeftRun& left) {
  Problem& problem = run.problem();
  int p1 = -1;
  checking([&] {
    H5File f(run.work(), H5File::Mode::Read);
    const RunHeader header = read_run_header(f);
    for (const auto& [name, value] : header.parameters)
      if (problem.parameters().has(name)) problem.parameters().set(name, value);
    run.summary().unknowns = header.unknowns;
    if (from && from->curve) p1 = problem.parameters().index(read_branch_table(from->file).parameter);
  });
  return run.publish_left(
      left, branch_fields(xdmf_path_for(run.out()), fields_of(problem, problem.parameters().index(parameter), p1),
                          &InterruptGuard::requested));
}

// The stepper for the traced problem; options it refuses are bad input.
std::unique_ptr<Continuation> make_stepper(Problem& traced, const TraceStart& start, const TraceSettings& settings,
                                           const std::string& scene_file) {
  try {
    return std::make_unique<Continuation>(traced, start.options, settings.newton, settings.lu);
  } catch (const std::exception& e) {
    throw CommandFailure::bad_input(fmt::format("{}: [continuation]: {}", scene_file, e.what()));
  }
}

// What the branch file holds before its branch: the run's header and record, the mesh, and where the
// run started from (the attribute of --from, --switch or --restart).
std::function<void(H5File&)> branch_header(const CommandRun& run, Problem& traced, const TraceStart& start,
                                           const TraceArguments& args, const std::optional<StoredStart>& from) {
  return [&run, &traced, &start, &args, from](H5File& f) {
    write_run_header(f, run.loaded(), traced);
    f.write_string("/problem/run", trace_run_record(run.loaded(), args));
    const SolutionFields sf = traced.fields(start.first_state());
    if (sf.mesh) write_mesh(f, "/mesh", *sf.mesh);
    if (from && from->curve) {
      f.set_attribute("/problem", "curve_from", args.from);
      f.set_attribute("/problem", "curve", args.curve);
    } else if (from) {
      f.set_attribute("/problem", from->switching ? "switched_at" : "restarted_from",
                      from->switching ? args.switch_at : args.restart);
    }
  };
}

// A signal stops `run` (and nothing once it is over).
struct ForwardedInterrupts {
  explicit ForwardedInterrupts(Continuation* run) { InterruptGuard::forward_to(run); }
  ~ForwardedInterrupts() { InterruptGuard::forward_to(nullptr); }
  ForwardedInterrupts(const ForwardedInterrupts&) = delete;
  ForwardedInterrupts& operator=(const ForwardedInterrupts&) = delete;
};

// Traces the branch from `start` with `stepper`. Each point goes to a curve's border update, then
// (continuing an unfinished run) is numbered after its rows, then goes to the file and the terminal
// (a curve's table shows its other parameter first).
ContinuationResult trace_branch(Continuation& stepper, TraceStart& start, const TraceSettings& settings,
                                BranchFile& file, Problem& scene_problem) {
  Problem* plain = start.curve ? nullptr : &scene_problem;
  ProgressPrinter printer(settings.continuation.parameter, 3,
                          start.curve ? std::vector<std::string>{start.curve->p1_name()} : std::vector<std::string>{});
  const std::unique_ptr<BranchObserver> hook = branch_hook(settings.continuation.parameter);
  ObserverList observers(hook ? std::vector<BranchObserver*>{&file, &printer, hook.get()}
                              : std::vector<BranchObserver*>{&file, &printer});
  std::optional<ContinuedBranch> continued;
  BranchObserver* observer = &observers;
  if (start.seed) observer = &continued.emplace(observers, start.seed->row);
  std::unique_ptr<BranchObserver> borders;
  if (start.borders) observer = (borders = start.borders(*observer)).get();
  // the normal forms of its located points, where the branch is one of the problem itself
  std::optional<NormalFormObserver> normal_forms;
  if (plain && start.begin != TraceStart::Begin::EventCurve)
    observer = &normal_forms.emplace(*observer, *plain, plain->parameters().index(settings.continuation.parameter),
                                     settings.lu);
  // the cusps, Bogdanov-Takens and fold-Hopf points of a fold or Hopf curve
  if (dynamic_cast<FoldCurveProblem*>(start.curve.get()) || dynamic_cast<HopfCurveProblem*>(start.curve.get()))
    observer = &normal_forms.emplace(NormalFormObserver::for_curve(
        *observer, scene_problem, start.curve->p1(), scene_problem.parameters().index(settings.continuation.parameter),
        start.curve->observable_names().size(), settings.lu));
  const ForwardedInterrupts forwarded(&stepper);
  switch (start.begin) {
    case TraceStart::Begin::State: return stepper.run(start.state, *observer, std::move(start.factorisation));
    case TraceStart::Begin::Point: return stepper.resume(*start.point, *observer);
    case TraceStart::Begin::Switch: {
      // the normal form's branch where it has one, else J's null vector
      std::optional<Continuation::SwitchPrediction> prediction;
      if (plain && settings.continuation.switch_normal_form) {
        std::string note;
        prediction = switch_prediction(*plain, plain->parameters().index(settings.continuation.parameter), *start.point,
                                       settings.lu, note);
        fmt::print("{}\n", note);
      }
      return stepper.switch_branch(*start.point, start.direction, *observer, prediction ? &*prediction : nullptr);
    }
    case TraceStart::Begin::EventCurve:
      return start.event_tracer->trace(start.options, settings.newton, settings.lu, start.state, *observer,
                                       [](Continuation* piece) { InterruptGuard::forward_to(piece); });
  }
  return {};
}

}  // namespace

int run_trace(const TraceArguments& args, RunSummary* out_summary) {
  if (args.orbit) return run_orbit_trace(args, out_summary);
  return run_command(out_summary, [&](RunSummary& summary) {
    CommandRun run(summary, kBranch);
    // 1. the scene, its options and the files of the run: nothing is written before all are right
    TraceSettings settings;
    run.load(args.scene, args.output, declare_trace_keys, args.overrides,
             [&](const Scene& scene) { settings = TraceSettings::from_scene(scene, args.free); });
    std::optional<StoredStart> from;
    run.check([&](RunFiles& files) { from = checked_start(args, settings, files, run); }, args.output_locked);
    Problem& problem = run.build([&](Problem& p) { refuse_problem(p, settings, run.scene()); });
    const std::string& parameter = settings.continuation.parameter;

    // 2. where the branch starts: an unfinished run of this command, a stored point, or a solve
    TraceSource source;
    checking([&] {
      source = read_trace_source(run, trace_run_record(run.loaded(), args), args.fresh, from, problem, parameter);
    });
    if (source.left.kind == LeftRun::Kind::ended) return publish_left_branch(run, from, parameter, source.left);
    for (const std::string& w : source.warnings) fmt::print(stderr, "keller: warning: {}\n", w);
    fmt::print("problem: {}\n", problem.summary());
    TraceStart start = trace_start(problem, settings, from, source, run.scene(), args.switch_direction);

    // 3. the branch, written to OUT.h5.part point by point
    Problem& traced = start.traced(problem);
    const std::unique_ptr<Continuation> stepper = make_stepper(traced, start, settings, args.scene);
    std::unique_ptr<StabilityAnalysis> stability;
    if (settings.stability.enabled) {
      stability = std::make_unique<StabilityAnalysis>(settings.stability, settings.lu);
      stepper->set_analysis(stability.get());
    }
    ContinuationResult result;
    const RunEnd end = run.write<BranchFile>(
        [&] {
          return std::make_unique<BranchFile>(run.work(), traced, start.options, stepper->monitor_names(),
                                              start.options.state_scale, branch_header(run, traced, start, args, from),
                                              stepper->analysis_columns(), start.seed ? &*start.seed : nullptr);
        },
        [&](BranchFile& file) {
          result = trace_branch(*stepper, start, settings, file, problem);
          return RunEnd{result.code == StopCode::Interrupted, is_failure(result.code)};
        });
    if (stability)
      fmt::print("stability: {:.2f} s in {} factorisations and {} solves of (J - sB)\n", stability->seconds(),
                 stability->factorisations(), stability->solves());
    report_branch_run(result, traced.size(), summary);
    if (start.seed) summary.continued_from = start.seed->row;

    // 4. the branch takes its name: an interrupted one stays where it is, to be continued; a
    // failed one never replaces an existing file
    const int p1 = start.curve ? start.curve->p1() : -1;
    return run.publish(
        end, branch_fields(xdmf_path_for(run.out()), fields_of(problem, problem.parameters().index(parameter), p1),
                           &InterruptGuard::requested));
  });
}

}  // namespace keller
