#include "runs/TraceCommand.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <limits>
#include <optional>

#include "continuation/Continuation.hpp"
#include "continuation/curves/EventCurveProblem.hpp"
#include "continuation/curves/FoldCurveProblem.hpp"
#include "continuation/curves/HopfCurveProblem.hpp"
#include "continuation/output/BranchFile.hpp"
#include "continuation/output/ContinuedBranch.hpp"
#include "continuation/output/ProgressPrinter.hpp"
#include "continuation/start/StartSolver.hpp"
#include "core/HeldFile.hpp"
#include "core/IoError.hpp"
#include "core/OutputLock.hpp"
#include "core/PendingFile.hpp"
#include "core/RunFiles.hpp"
#include "core/SignalPoint.hpp"
#include "core/SolutionWriter.hpp"
#include "runs/BranchOutput.hpp"
#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/StoredStart.hpp"
#include "stability/StabilityAnalysis.hpp"

namespace keller {

namespace fs = std::filesystem;

void declare_trace_keys(SceneSchema& schema) {
  ContinuationOptions::declare(schema);
  StabilityOptions::declare(schema);
}

std::string trace_run_record(const LoadedScene& loaded, const TraceArguments& a) {
  std::string start = "steady state";
  if (!a.restart.empty()) start = "restart " + a.restart;
  if (!a.switch_at.empty()) start = fmt::format("switch {} {}", a.switch_at, a.switch_direction);
  if (!a.from.empty()) start = fmt::format("{} curve from {} in {}", a.curve, a.from, a.free);
  return loaded.scene.canonical_values() + fmt::format("start = {}\n", start);
}

namespace {

struct Unfinished {
  BranchSeed seed;
  BranchPoint point;
  double state_scale = 0, theta = 0;
};

// The unfinished run of this very command at `work`, to be continued; `left` says what `work` holds
// (left_run: an ended run of this command is published instead).
std::optional<Unfinished> unfinished_run(const std::string& work, const std::string& record,
                                         const std::string& defaults, bool fresh, LeftRun& left) {
  BranchTable t;
  left = left_run(work, record, defaults, fresh, "branch", "rows", "/branch/exit_code", [&](const std::string& path) {
    t = read_branch_table(path);
    return std::pair<long, std::string>(t.rows.rows(), t.status);
  });
  if (left.kind != LeftRun::Kind::unfinished) return {};
  Unfinished u;
  u.seed = read_branch_seed(work);
  u.point = read_branch_point(work, u.seed.row);
  u.state_scale = t.state_scale;
  u.theta = t.theta;
  return u;
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

// The ended run of this command in `work`, killed before it took its name: published now, at the
// parameter values it was traced at (a curve's second parameter from its --from branch).
int publish_left_branch(const std::string& work, const std::string& out, bool with_fields,
                        const std::optional<StoredStart>& from, Problem& problem, const std::string& parameter,
                        const LeftRun& left, RunSummary& summary) {
  RunHeader header;
  {
    H5File f(work, H5File::Mode::Read);
    header = read_run_header(f);
  }
  for (const auto& [name, value] : header.parameters)
    if (problem.parameters().has(name)) problem.parameters().set(name, value);
  summary.unknowns = header.unknowns;
  const int p1 = from && from->curve ? problem.parameters().index(read_branch_table(from->file).parameter) : -1;
  return publish_left_run(
      work, out, with_fields,
      branch_fields(xdmf_path_for(out), fields_of(problem, problem.parameters().index(parameter), p1),
                    &InterruptGuard::requested),
      left, "branch", summary);
}

}  // namespace

int run_trace(const TraceArguments& args, RunSummary* out_summary) {
  RunSummary local;
  RunSummary& summary = out_summary ? *out_summary : local;
  summary = {};
  auto fail = [&](int code, const std::string& message) {
    fmt::print(stderr, "keller: error: {}\n", message);
    summary.exit_code = code;
    summary.reason = message;
    return code;
  };
  // a numerical failure before anything is written: what failed and why
  auto failed = [&](const std::string& what, const Status& st) {
    fmt::print(stderr, "keller: {}: {}; no output written\n", what, st.describe());
    summary.reason = what + ": " + st.describe();
    summary.exit_code = exit_code::numerical_failure;
    return summary.exit_code;
  };
  LoadedScene loaded;
  std::unique_ptr<Problem> problem;
  ContinuationOptions copt;
  StabilityOptions sopt;
  std::optional<StoredStart> from;
  // 1. the scene, its options and the files of the run: nothing is written before all are right
  try {
    loaded = load_scene(args.scene, declare_trace_keys, args.overrides);
    check_memory(loaded);
    copt = ContinuationOptions::from_scene(loaded.scene);
    sopt = StabilityOptions::from_scene(loaded.scene);
    if (!args.free.empty()) copt.parameter = args.free;
  } catch (const SceneError& e) {
    return fail(exit_code::usage, e.what());
  } catch (const std::exception& e) {
    return fail(exit_code::usage, fmt::format("{}: {}", args.scene, e.what()));
  }
  const std::string out = args.output.empty() ? fs::path(args.scene).stem().string() + ".h5" : args.output;
  const std::string work = PendingFile::temporary_for(out);
  const bool with_fields = loaded.scene.boolean("output.xdmf");
  OutputLock lock;  // one run at a time writes `out`
  try {
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
    if (!args.from.empty() && sopt.enabled)
      throw std::invalid_argument(
          "[stability]: the points of a curve are not analysed; trace ordinary branches "
          "at the curve's parameter values for their stability");
    RunFiles files;
    files.input("scene file", args.scene);
    if (!args.restart.empty()) from = parse_stored_start("--restart", args.restart);
    if (!args.switch_at.empty()) from = parse_stored_start("--switch", args.switch_at);
    if (!args.from.empty()) {
      from = parse_stored_start("--from", args.from);
      from->located = args.curve == "event"  ? PointKind::Event
                      : args.curve == "hopf" ? PointKind::Hopf
                                             : PointKind::Fold;
    }
    if (from) {
      from->force = args.force;
      files.input(from->flag + " file", from->file);
    }
    declare_run_outputs(files, out, "branch file", with_fields);
    files.check();
    if (!args.output_locked) lock = OutputLock(OutputLock::path_for(out), "'" + out + "'");
  } catch (const std::exception& e) {
    return fail(exit_code::usage, e.what());
  }
  fmt::print("{}\n", scene_summary(loaded, out));
  try {
    problem = loaded.type->build(loaded.scene);
    if (!problem->parameters().has(copt.parameter))
      throw loaded.scene.error("continuation.parameter", "unknown parameter '" + copt.parameter +
                                                             "'; this problem has: " + problem->parameters().names());
    if (sopt.enabled) sopt.check_size(loaded.scene, problem->size());
  } catch (const SceneError& e) {
    return fail(exit_code::usage, e.what());
  } catch (const std::exception& e) {
    return fail(exit_code::usage, fmt::format("{}: {}", args.scene, e.what()));
  }
  // 2. where the branch starts: an unfinished run of this command, a stored point, or a solve
  const std::string record = trace_run_record(loaded, args);
  std::optional<Unfinished> unfinished;
  std::optional<StoredPoint> stored;
  std::optional<BranchPoint> start;
  bool other_parameter = false;  // a restart from a branch traced in another parameter
  std::vector<std::string> warnings;
  LeftRun left;
  try {
    unfinished = unfinished_run(work, record, loaded.defaults(), args.fresh, left);
    if (left.kind == LeftRun::Kind::ended)
      return publish_left_branch(work, out, with_fields, from, *problem, copt.parameter, left, summary);
    if (unfinished) {
      start = unfinished->point;
      copt.state_scale = unfinished->state_scale;
      copt.theta = unfinished->theta;
    } else if (from) {
      stored = read_stored_start(*from, loaded, *problem, copt.parameter, warnings);
      start = stored->point;
      other_parameter = stored->table.parameter != copt.parameter;
      if (other_parameter) {
        // a new branch in another parameter from a state of the stored one: its start value is the
        // point's, and its tangent and state scale are its own
        const std::optional<double> v = stored->value_of(copt.parameter);
        if (!v)
          throw std::invalid_argument(
              fmt::format("{}: '{}' does not record the value of '{}'", from->flag, from->file, copt.parameter));
        start->lambda = *v;
      } else {
        copt.state_scale = stored->table.state_scale;
        copt.theta = stored->table.theta;
      }
    }
  } catch (const std::exception& e) {
    return fail(exit_code::usage, e.what());
  }
  try {
    if (from && from->curve && !stored) stored = read_stored_start(*from, loaded, *problem, copt.parameter, warnings);
  } catch (const std::exception& e) {
    return fail(exit_code::usage, e.what());
  }
  for (const std::string& w : warnings) fmt::print(stderr, "keller: warning: {}\n", w);
  const Scene& scene = loaded.scene;
  fmt::print("problem: {}\n", problem->summary());
  const NewtonOptions nopt = newton_options_from(scene);
  const SparseLUOptions lopt = sparse_lu_options_from(scene);

  Vector u0;
  StartFactorisation start_factorisation;          // the first state's last factorisation of J, handed to the branch
  std::unique_ptr<FoldCurveProblem> curve;         // --curve fold: the augmented problem traced instead
  std::unique_ptr<EventCurveProblem> event_curve;  // --curve event
  std::unique_ptr<HopfCurveProblem> hopf_curve;    // --curve hopf
  if (from && from->curve && from->located == PointKind::Event) {
    for (const Parameter& q : problem->parameters().list())
      if (const auto v = stored->value_of(q.name)) problem->parameters().set(q.name, *v);
    const BranchPoint& event = stored->point;
    // the monitor whose zero the row is: an event's label, or the stop observable's ("min_m1 < stop_below")
    std::string monitor;
    const std::string label =
        event.label.empty() ? located_monitor(from->file, event.index, stored->table) : event.label;
    for (const std::string& m : problem->monitor_names())
      if (label == m || label.rfind(m + " ", 0) == 0) monitor = m;
    if (monitor.empty())
      return fail(exit_code::usage,
                  fmt::format("--from '{}': row {} ({}) is not the zero of a monitor of this problem "
                              "({})",
                              from->file, event.index, label,
                              problem->monitor_names().empty()
                                  ? std::string("it has none")
                                  : "its monitors: " + fmt::format("{}", fmt::join(problem->monitor_names(), ", "))));
    if (!copt.stop.observable.empty()) {
      fmt::print(
          "note: continuation.stop_observable ({}) is left aside: an event curve's pieces end where the "
          "minimum's place moves\n",
          copt.stop.observable);
      copt.stop.observable.clear();
    }
    event_curve = std::make_unique<EventCurveProblem>(*problem, stored->table.parameter, monitor);
    Vector U = event_curve->state(event.u, event.lambda);
    if (unfinished) {
      problem->parameters().set(copt.parameter, start->lambda);
      U = start->u;
    }
    const Status st = event_curve->start(U, nopt, lopt);
    if (!st.is_ok()) {
      return failed("the event curve's first point failed", st);
    }
    fmt::print(
        "event curve of {} = 0 in ({}, {}) from row {} of {} ({} = {:.10g}, {} = {:.10g}), the minimum at place "
        "{}\n",
        monitor, copt.parameter, stored->table.parameter, event.index, from->file, stored->table.parameter,
        U[U.size() - 1], copt.parameter, problem->parameters().get(copt.parameter), event_curve->place());
    if (unfinished)
      fmt::print("continuing the unfinished curve in {} from its row {} ({} = {:.10g}; --fresh starts over)\n", work,
                 unfinished->seed.row, copt.parameter, start->lambda);
    u0 = U;
    start.reset();
  } else if (from && from->curve && from->located == PointKind::Hopf) {
    for (const Parameter& q : problem->parameters().list())
      if (const auto v = stored->value_of(q.name)) problem->parameters().set(q.name, *v);
    const BranchPoint& hopf = stored->point;
    Vector re, im;
    double omega = 0.0;
    if (!read_critical_mode(from->file, hopf.index, re, im, omega))
      return fail(exit_code::usage, fmt::format("--from '{}': row {} has no stored critical eigenvector (a Hopf point "
                                                "of a branch traced with [stability] has one)",
                                                from->file, hopf.index));
    hopf_curve = std::make_unique<HopfCurveProblem>(*problem, stored->table.parameter, lopt);
    Vector U = hopf_curve->state(hopf.u, hopf.lambda, std::abs(omega));
    const ComplexVector mode = re.cast<std::complex<double>>() + std::complex<double>(0.0, 1.0) * im;
    Status st = hopf_curve->start(U, mode, nopt, lopt);
    if (st.is_ok() && unfinished) {
      // the borders from the start's eigenvector, refined at the point the unfinished curve continues from
      ComplexVector v, w;
      std::complex<double> g;
      st = hopf_curve->null_vectors(U, v, w, g);
      problem->parameters().set(copt.parameter, start->lambda);
      if (st.is_ok()) st = hopf_curve->set_borders(start->u, v);
    }
    if (!st.is_ok()) {
      return failed("the Hopf curve's first point failed", st);
    }
    fmt::print(
        "Hopf curve in ({}, {}) from the Hopf point at row {} of {} ({} = {:.10g}, omega = {:.10g}, {} = {:.10g})\n",
        copt.parameter, stored->table.parameter, hopf.index, from->file, stored->table.parameter, U[U.size() - 2],
        U[U.size() - 1], copt.parameter, problem->parameters().get(copt.parameter));
    if (unfinished)
      fmt::print("continuing the unfinished curve in {} from its row {} ({} = {:.10g}; --fresh starts over)\n", work,
                 unfinished->seed.row, copt.parameter, start->lambda);
    else {
      u0 = U;
      start.reset();
    }
  } else if (from && from->curve) {
    for (const Parameter& q : problem->parameters().list())
      if (const auto v = stored->value_of(q.name)) problem->parameters().set(q.name, *v);
    const BranchPoint& fold = stored->point;
    curve = std::make_unique<FoldCurveProblem>(*problem, stored->table.parameter, lopt);
    Vector U = curve->state(fold.u, fold.lambda);
    const Status st = curve->start(U, fold.tu, nopt, lopt);
    if (!st.is_ok()) {
      return failed("the fold curve's first point failed", st);
    }
    fmt::print("fold curve in ({}, {}) from the fold at row {} of {} ({} = {:.10g}, {} = {:.10g})\n", copt.parameter,
               stored->table.parameter, fold.index, from->file, stored->table.parameter, U[U.size() - 1],
               copt.parameter, problem->parameters().get(copt.parameter));
    if (unfinished) {
      // the borders from the fold's null vector, refined at the point the unfinished curve continues from
      Vector v, w;
      double g = 0.0;
      Status b = curve->null_vectors(U, v, w, g);
      problem->parameters().set(copt.parameter, start->lambda);
      if (b.is_ok()) b = curve->set_borders(start->u, v);
      if (!b.is_ok()) {
        return failed("the unfinished fold curve cannot be continued", b);
      }
      fmt::print("continuing the unfinished curve in {} from its row {} ({} = {:.10g}; --fresh starts over)\n", work,
                 unfinished->seed.row, copt.parameter, start->lambda);
    } else {
      u0 = U;
      start.reset();
    }
  } else if (other_parameter) {
    for (const Parameter& q : problem->parameters().list())
      if (const auto v = stored->value_of(q.name)) problem->parameters().set(q.name, *v);
    u0 = start->u;
    fmt::print("starting a branch in {} at row {} of {}, a branch in {} ({} = {:.10g}, {} = {:.10g})\n", copt.parameter,
               start->index, from->file, stored->table.parameter, stored->table.parameter, stored->point.lambda,
               copt.parameter, start->lambda);
    const std::string key = "parameters." + copt.parameter;
    if (loaded.scene.schema().find(key) && loaded.scene.real(key) != start->lambda)
      fmt::print("note: {} starts at the stored point's value {:.10g}, not at the scene's {}\n", copt.parameter,
                 start->lambda, loaded.scene.real(key));
    start.reset();
  } else if (start) {
    problem->parameters().set(copt.parameter, start->lambda);
    if (unfinished)
      fmt::print("continuing the unfinished branch in {} from its row {} ({} = {:.10g}; --fresh starts over)\n", work,
                 unfinished->seed.row, copt.parameter, start->lambda);
    else
      fmt::print("{} row {} of {} ({} = {:.10g})\n", from->switching ? "switching branches at" : "restarting from",
                 start->index, from->file, copt.parameter, start->lambda);
  } else {
    StartSolver start_solver(*problem, nopt, lopt, StartOptions::from_scene(loaded.scene),
                             [](const std::string& line) { fmt::print("{}\n", line); });
    u0 = problem->initial_guess();
    fmt::print("first steady state at {} = {}\n", copt.parameter, problem->parameters().get(copt.parameter));
    print_newton_header();
    const StartResult r = start_solver.solve(u0, print_newton_row);
    if (!r.status.is_ok()) {
      return failed("the first steady state failed", r.status);
    }
    fmt::print("first steady state: {}, {} Newton iterations, {} factorisations, {:.2f} s\n", r.path,
               r.newton_iterations, r.factorisations, r.seconds);
    start_factorisation = {r.factorisation, r.jacobian, r.factorised_at};
  }

  // 3. the branch, written to `work` point by point
  CurveProblem* traced_curve = curve         ? static_cast<CurveProblem*>(curve.get())
                               : event_curve ? static_cast<CurveProblem*>(event_curve.get())
                               : hopf_curve  ? static_cast<CurveProblem*>(hopf_curve.get())
                                             : nullptr;
  Problem& traced = traced_curve ? *traced_curve : *problem;
  ContinuationOptions fixed = copt;
  if (event_curve) {  // each piece of the curve ends where the minimum's place moves
    fixed.stop.observable = EventCurveProblem::kMargin;
    fixed.stop.below = 0.0;
    fixed.stop.above = std::numeric_limits<double>::infinity();
  }
  if (!(fixed.state_scale > 0)) {  // a new run's state scale is the RMS of its start
    const double rms = u0.norm() / std::sqrt(static_cast<double>(std::max<long>(u0.size(), 1)));
    fixed.state_scale = rms > 0 ? rms : 1.0;
  }
  std::unique_ptr<Continuation> run;
  try {
    run = std::make_unique<Continuation>(traced, fixed, nopt, lopt);
  } catch (const std::exception& e) {
    return fail(exit_code::usage, fmt::format("{}: [continuation]: {}", args.scene, e.what()));
  }
  std::unique_ptr<StabilityAnalysis> stability;
  if (sopt.enabled) {
    stability = std::make_unique<StabilityAnalysis>(sopt, lopt);
    run->set_analysis(stability.get());
  }
  InterruptGuard interrupts;
  ContinuationResult result;
  HeldFile written;  // the file this run writes, to be published
  {
    std::unique_ptr<BranchFile> file;
    try {
      file = std::make_unique<BranchFile>(
          work, traced, fixed, run->monitor_names(), fixed.state_scale,
          [&](H5File& f) {
            write_run_header(f, loaded, traced);
            f.write_string("/problem/run", record);
            const SolutionFields sf = traced.fields(start ? start->u : u0);
            if (sf.mesh) write_mesh(f, "/mesh", *sf.mesh);
            if (from && from->curve) {
              f.set_attribute("/problem", "curve_from", args.from);
              f.set_attribute("/problem", "curve", args.curve);
            } else if (from)
              f.set_attribute("/problem", from->switching ? "switched_at" : "restarted_from",
                              from->switching ? args.switch_at : args.restart);
          },
          run->analysis_columns(), unfinished ? &unfinished->seed : nullptr);
      written = std::move(file->written());
    } catch (const IoError& e) {
      return fail(exit_code::io_failure, fmt::format("{}; nothing written", e.what()));
    } catch (const std::exception& e) {
      return fail(exit_code::usage, e.what());
    }
    // a curve's table shows its other parameter (an observable of the curve) first
    ProgressPrinter printer(
        copt.parameter, 3,
        traced_curve ? std::vector<std::string>{stored->table.parameter} : std::vector<std::string>{});
    ObserverList observers({file.get(), &printer});
    std::optional<ContinuedBranch> continued;
    BranchObserver* observer = &observers;
    if (unfinished) observer = &continued.emplace(observers, unfinished->seed.row);
    std::optional<FoldCurveProblem::BorderUpdate> borders;
    if (curve) observer = &borders.emplace(*curve, *observer);
    std::optional<HopfCurveProblem::BorderUpdate> hopf_borders;
    if (hopf_curve) observer = &hopf_borders.emplace(*hopf_curve, *observer);
    InterruptGuard::forward_to(run.get());
    const std::optional<int> stopped = write_run_file(
        work, out, written, "branch", "point",
        [&] {
          result = event_curve               ? event_curve->trace(fixed, nopt, lopt, u0, *observer,
                                                                  [](Continuation* c) { InterruptGuard::forward_to(c); })
                   : unfinished              ? run->resume(*start, *observer)
                   : from && from->switching ? run->switch_branch(*start, args.switch_direction, *observer)
                   : start                   ? run->resume(*start, *observer)
                                             : run->run(u0, *observer, std::move(start_factorisation));
          return RunEnd{result.code == StopCode::Interrupted, is_failure(result.code)};
        },
        [&](std::optional<int> code) { file->finish(code); }, summary);
    InterruptGuard::forward_to(nullptr);
    if (stopped) return *stopped;
  }
  if (stability)
    fmt::print("stability: {:.2f} s in {} factorisations and {} solves of (J - sB)\n", stability->seconds(),
               stability->factorisations(), stability->solves());
  report_branch_run(result, traced.size(), summary);
  if (unfinished) summary.continued_from = unfinished->seed.row;

  // 4. the branch takes its name: an interrupted one stays where it is, to be continued; a
  // failed one never replaces an existing file
  if (const auto stays = stays_unfinished(result.code == StopCode::Interrupted, is_failure(result.code), work, out,
                                          "branch", "before its range", summary))
    return *stays;
  const int code = summary.exit_code;
  signal_point("traced");
  const FieldsAt fields =
      fields_of(*problem, problem->parameters().index(copt.parameter), traced_curve ? traced_curve->p1() : -1);
  return publish_run(work, out, with_fields, branch_fields(xdmf_path_for(out), fields, &InterruptGuard::requested),
                     written, code, "branch", summary);
}

}  // namespace keller
