#include "runs/TraceCommand.hpp"

#include <fmt/format.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include "continuation/BranchFile.hpp"
#include "continuation/Continuation.hpp"
#include "continuation/ProgressPrinter.hpp"
#include "continuation/StartSolver.hpp"
#include "core/SolutionWriter.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"
#include "stability/StabilityAnalysis.hpp"

namespace keller {

namespace {

Continuation* g_running = nullptr;

extern "C" void on_signal(int) {
  if (g_running) g_running->request_stop();
}

struct RestartSpec {
  std::string file;
  int row = -1;  // -1: last stored
};

RestartSpec parse_restart(const std::string& s) {
  const auto colon = s.rfind(':');
  if (colon == std::string::npos) throw std::invalid_argument("--restart needs FILE.h5:ROW (ROW a number or 'last')");
  RestartSpec r{s.substr(0, colon), -1};
  const std::string row = s.substr(colon + 1);
  if (row != "last") {
    try {
      size_t used = 0;
      r.row = std::stoi(row, &used);
      if (used != row.size() || r.row < 0) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw std::invalid_argument("--restart: '" + row + "' is not a row number or 'last'");
    }
  }
  return r;
}

}  // namespace

void declare_trace_keys(SceneSchema& schema) {
  ContinuationOptions::declare(schema);
  StabilityOptions::declare(schema);
}

int run_trace(const TraceArguments& args) {
  namespace fs = std::filesystem;
  LoadedScene loaded;
  std::unique_ptr<Problem> problem;
  ContinuationOptions copt;
  std::string out = args.output;
  std::optional<RestartSpec> restart;
  std::optional<BranchPoint> restart_point;
  StabilityOptions sopt;
  const bool switching = !args.switch_at.empty();
  try {
    loaded = load_scene(args.scene, declare_trace_keys, args.overrides);
    copt = ContinuationOptions::from_scene(loaded.scene);
    sopt = StabilityOptions::from_scene(loaded.scene);
    if (!args.restart.empty() && !args.switch_at.empty())
      throw std::invalid_argument("--restart and --switch exclude each other");
    if (out.empty()) out = fs::path(args.scene).stem().string() + ".h5";
    check_output_path(out);
    if (!args.restart.empty() || switching) {
      const std::string flag = switching ? "--switch" : "--restart";
      restart = parse_restart(switching ? args.switch_at : args.restart);
      if (fs::absolute(restart->file) == fs::absolute(out))
        throw std::invalid_argument(flag + " reads '" + restart->file + "': write the new branch to another file");
      const BranchTable t = read_branch_table(restart->file);
      if (t.parameter != copt.parameter)
        throw std::invalid_argument(fmt::format("{}: '{}' continues in '{}', the scene in '{}'", flag, restart->file,
                                                t.parameter, copt.parameter));
      restart_point = read_branch_point(restart->file, restart->row);
      copt.state_scale = t.state_scale;
      copt.theta = t.theta;
    }
    fmt::print("{}\n", loaded.scene.resolved_toml());
    problem = loaded.type->build(loaded.scene);
    if (!problem->parameters().has(copt.parameter))
      throw loaded.scene.error("continuation.parameter", "unknown parameter '" + copt.parameter +
                                                             "'; this problem has: " + problem->parameters().names());
  } catch (const SceneError& e) {
    fmt::print(stderr, "keller: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: {}: {}\n", args.scene, e.what());
    return 2;
  }
  const Scene& scene = loaded.scene;
  fmt::print("problem: {}\n", problem->summary());
  const NewtonOptions nopt = newton_options_from(scene);
  const SparseLUOptions lopt = sparse_lu_options_from(scene);

  Vector u0;
  StartFactorisation start_factorisation;  // the first state's last factorisation of J
  if (restart_point) {
    if (restart_point->u.size() != problem->size()) {
      fmt::print(stderr, "keller: error: --restart: stored point has {} unknowns, this scene's problem {}\n",
                 restart_point->u.size(), problem->size());
      return 2;
    }
    problem->parameters().set(copt.parameter, restart_point->lambda);
    fmt::print("{} row {} of {} ({} = {:.10g})\n", switching ? "switching branches at" : "restarting from",
               restart_point->index, restart->file, copt.parameter, restart_point->lambda);
  } else {
    StartSolver start(*problem, nopt, lopt, StartOptions::from_scene(scene),
                      [](const std::string& line) { fmt::print("{}\n", line); });
    u0 = problem->initial_guess();
    fmt::print("first steady state at {} = {}\n", copt.parameter, problem->parameters().get(copt.parameter));
    print_newton_header();
    const StartResult r = start.solve(u0, print_newton_row);
    if (!r.status.is_ok()) {
      fmt::print(stderr, "keller: the first steady state failed: {}; no output written\n", r.status.describe());
      return 1;
    }
    fmt::print("first steady state: {}, {} Newton iterations, {} factorisations, {:.2f} s\n", r.path,
               r.newton_iterations, r.factorisations, r.seconds);
    start_factorisation = {r.factorisation, r.jacobian, r.factorised_at};
  }

  ContinuationResult result;
  {
    // the state scale is fixed when the run starts; for a new run it is the start's RMS
    double scale = copt.state_scale;
    if (!(scale > 0)) {
      const double rms = u0.norm() / std::sqrt(static_cast<double>(std::max<long>(u0.size(), 1)));
      scale = rms > 0 ? rms : 1.0;
    }
    ContinuationOptions fixed = copt;
    fixed.state_scale = scale;
    std::unique_ptr<Continuation> run_ptr;
    try {
      run_ptr = std::make_unique<Continuation>(*problem, fixed, nopt, lopt);
    } catch (const std::exception& e) {
      fmt::print(stderr, "keller: error: {}: [continuation]: {}\n", args.scene, e.what());
      return 2;
    }
    Continuation& run = *run_ptr;
    std::unique_ptr<StabilityAnalysis> stability;
    if (sopt.enabled) {
      stability = std::make_unique<StabilityAnalysis>(sopt, lopt);
      run.set_analysis(stability.get());
    }
    std::unique_ptr<BranchFile> file;
    try {
      file = std::make_unique<BranchFile>(out, *problem, fixed, run.monitor_names(), scale, [&](H5File& f) {
        write_run_header(f, scene, *problem);
        const SolutionFields sf = problem->fields(restart_point ? restart_point->u : u0);
        if (sf.mesh) write_mesh(f, "/mesh", *sf.mesh);
        if (restart_point) f.set_attribute("/problem", switching ? "switched_at" : "restarted_from",
                                           switching ? args.switch_at : args.restart);
      }, run.analysis_columns());
    } catch (const std::exception& e) {
      fmt::print(stderr, "keller: error: {}\n", e.what());
      return 2;
    }
    ProgressPrinter printer(copt.parameter);
    ObserverList observers({file.get(), &printer});
    g_running = &run;
    auto old_int = std::signal(SIGINT, on_signal);
    auto old_term = std::signal(SIGTERM, on_signal);
    result = switching       ? run.switch_branch(*restart_point, args.switch_direction, observers)
             : restart_point ? run.resume(*restart_point, observers)
                             : run.run(u0, observers, start_factorisation);
    std::signal(SIGINT, old_int);
    std::signal(SIGTERM, old_term);
    g_running = nullptr;
    file->close();
    if (stability)
      fmt::print("stability: {} s in {} factorisations and {} solves of (J - sB)\n", stability->seconds(),
                 stability->factorisations(), stability->solves());
  }
  fmt::print("{} points, {} rejected steps, {} factorisations ({:.2f} per point; {} of them branch-point probes), {} "
             "tangent solves by iteration, renewal cost {:.1f} solves; {}\n",
             result.points, result.rejected, result.factorisations,
             result.points > 0 ? static_cast<double>(result.factorisations) / result.points : 0.0, result.probes,
             result.tangent_iterations, result.renewal_cost, result.reason);
  const ContinuationTimings& tm = result.timings;
  fmt::print("time {:.2f} s: factorisations {:.2f}, solves {:.2f} ({}), Jacobians {:.2f} ({}), dF/dp {:.2f}, residuals {:.2f} ({}), "
             "observables {:.2f}, stability {:.2f} ({} spectra), output {:.2f}, other {:.2f}\n",
             tm.total, tm.factorisation, tm.solve, tm.solves, tm.jacobian, tm.jacobians, tm.parameter_derivative, tm.residual,
             tm.residuals, tm.observables, tm.analysis, tm.analyses, tm.output,
             tm.total - tm.factorisation - tm.solve - tm.jacobian - tm.parameter_derivative - tm.residual -
                 tm.observables - tm.analysis - tm.output);

  if (scene.boolean("output.xdmf")) {
    try {
      const int p = problem->parameters().index(copt.parameter);
      auto fields_at = [&](const Vector& u, double lambda) {
        problem->parameters().set(p, lambda);
        return problem->fields(u);
      };
      const std::string xdmf = xdmf_path_for(out);
      write_branch_fields(out, out, xdmf, fields_at);
      const std::string stem = xdmf.substr(0, xdmf.size() - std::string(".xdmf").size());
      const int modes = write_branch_modes(out, stem, fields_at);
      if (modes > 0) fmt::print("wrote {} critical eigenmode(s): {}_mode<k>.xdmf\n", modes, stem);
    } catch (const std::exception& e) {
      fmt::print(stderr, "keller: warning: fields/XDMF not written: {}\n", e.what());
    }
  }
  fmt::print("wrote {}\n", out);
  switch (result.code) {
    case StopCode::StepFloor: return 1;
    case StopCode::Interrupted: return 130;
    default: return 0;
  }
}

int run_export(const ExportArguments& args) {
  namespace fs = std::filesystem;
  if (args.csv.empty() && !args.xdmf) {
    fmt::print(stderr, "keller: error: export needs --csv FILE and/or --xdmf\n");
    return 2;
  }
  try {
    const BranchTable t = read_branch_table(args.input);
    if (!args.csv.empty()) {
      check_output_path(args.csv);
      const std::string part = args.csv + ".part";
      {
        std::ofstream o(part);
        for (size_t j = 0; j < t.columns.size(); ++j) o << (j ? "," : "") << t.columns[j];
        o << "\n";
        for (long i = 0; i < t.rows.rows(); ++i) {
          for (long j = 0; j < t.rows.cols(); ++j) o << (j ? "," : "") << fmt::format("{:.17g}", t.rows(i, j));
          o << "\n";
        }
        if (!o) throw std::runtime_error("cannot write '" + part + "'");
      }
      fs::rename(part, args.csv);
      fmt::print("wrote {} ({} rows; status: {})\n", args.csv, t.rows.rows(), t.status);
    }
    if (args.xdmf) {
      // rebuild the problem from the scene stored in the file
      std::string scene_text;
      {
        H5File f(args.input, H5File::Mode::Read);
        scene_text = f.read_string("/scene");
      }
      const std::string tmp = (fs::temp_directory_path() / fmt::format("keller_scene_{}.toml", ::getpid())).string();
      std::ofstream(tmp) << scene_text;
      LoadedScene loaded = load_scene(tmp, declare_trace_keys);
      fs::remove(tmp);
      auto problem = loaded.type->build(loaded.scene);
      const int p = problem->parameters().index(t.parameter);
      // a file left open by a killed writer cannot take more datasets: use a companion file
      std::string fields_path = args.input;
      try {
        H5File probe(args.input, H5File::Mode::ReadWrite);
      } catch (const std::exception&) {
        fields_path = (fs::path(args.input).parent_path() / (fs::path(args.input).stem().string() + "-fields.h5")).string();
      }
      write_branch_fields(args.input, fields_path, xdmf_path_for(args.input), [&](const Vector& u, double lambda) {
        problem->parameters().set(p, lambda);
        return problem->fields(u);
      });
      fmt::print("wrote fields to {} and {}\n", fields_path, xdmf_path_for(args.input));
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: {}\n", e.what());
    return 2;
  }
  return 0;
}

}  // namespace keller
