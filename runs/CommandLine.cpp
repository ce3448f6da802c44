#include "runs/CommandLine.hpp"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <functional>

#include <sys/auxv.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#include "continuation/engine/ContinuationOptions.hpp"
#include "core/BlasThreads.hpp"
#include "runs/EvolveCommand.hpp"
#include "runs/ExitCode.hpp"
#include "runs/ExportCommand.hpp"
#include "runs/InfoCommand.hpp"
#include "runs/Provenance.hpp"
#include "runs/RunSummary.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/SolveCommand.hpp"
#include "runs/TraceCommand.hpp"
#include "runs/study/StudyCommand.hpp"

namespace {

// An option given an empty word ("-o ''") of the parsed commands: an error, not the default name.
void refuse_empty_values(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands()) {
    for (const CLI::Option* o : sub->get_options())
      for (const std::string& value : o->results())
        if (value.empty()) throw CLI::ValidationError(o->get_name(), "an empty path or value is not allowed");
    refuse_empty_values(*sub);
  }
}

int run(int argc, char** argv) {  // argc and argv go on to MPI_Init under mpirun
  CLI::App app{"keller: continuation and bifurcation toolkit for steady flows"};
  app.require_subcommand(1);
  app.footer(keller::exit_code::help);
  const std::string blas = keller::blas_core();
  app.set_version_flag("--version",
                       keller::Provenance::current().version_text() +
                           (blas.empty() ? std::string() : "\nBLAS: OpenBLAS, " + blas + " kernels"),
                       "print keller's version, commit, build type and linear solver, and exit");

  keller::SolveArguments solve;
  bool solve_help_scene = false;
  CLI::App* cmd_solve = app.add_subcommand("solve", "solve one steady state of a scene by Newton's method");
  cmd_solve->add_option("scene", solve.scene, "scene file (TOML)");
  cmd_solve->add_option("-o,--output", solve.output, "output HDF5 file (default: <scene name>.h5 here)");
  cmd_solve->add_option("--set", solve.overrides, "override a scene key: section.key=value (repeatable)");
  cmd_solve->add_flag("--check-jacobian", solve.check_jacobian,
                      "check J and dF/dp against central differences of the residual before solving (exit 1 if wrong)");
  cmd_solve->add_flag("--help-scene", solve_help_scene, "list every scene key with its default, range and doc");
  cmd_solve->footer(keller::exit_code::help);

  keller::TraceArguments trace;
  bool trace_help_scene = false;
  CLI::App* cmd_trace = app.add_subcommand("trace", "trace a solution branch by pseudo-arclength continuation");
  cmd_trace->add_option("scene", trace.scene, "scene file (TOML) with a [continuation] section");
  cmd_trace->add_option(
      "-o,--output", trace.output,
      "branch file (HDF5; default: <scene name>.h5 here); written as OUT.h5.part until the branch ends");
  cmd_trace->add_option(
      "--restart", trace.restart,
      "continue from a stored point: FILE.h5:ROW (ROW a number, 'last' or a located point's label such as "
      "stop2 or fold1: keller info FILE.h5 lists them)");
  cmd_trace->add_option(
      "--switch", trace.switch_at,
      "start a new branch at the located branch point stored in FILE.h5:ROW (or FILE.h5:bp1, ...), along the "
      "null vector of J; with --orbit, the doubled branch at a period doubling of an orbit branch (ORBITS.h5:pd1)");
  cmd_trace->add_option("--switch-direction", trace.switch_direction, "side of the old branch to switch to: 1 or -1")
      ->check(CLI::IsMember({-1, 1}));
  cmd_trace->add_option(
      "--from", trace.from,
      "start a curve at the located point stored in FILE.h5:ROW (or FILE.h5:fold1, hopf1, event1, end: a fold, "
      "Hopf point or event), its branch's parameter an unknown of the curve");
  cmd_trace
      ->add_option("--curve", trace.curve,
                   "the curve --from continues in a second parameter: fold (of a located fold), hopf (of a "
                   "located Hopf point of a branch traced with its stability) or event (the zero of a monitor, "
                   "min_m1 = 0: a located event or monitor end)")
      ->check(CLI::IsMember({"fold", "hopf", "event"}));
  cmd_trace->add_flag("--orbit", trace.orbit,
                      "trace the branch of periodic orbits born at the located Hopf point --from names, or through "
                      "the last state of the keller evolve run --from RUN.h5 names, or with --switch ORBITS.h5:pdK "
                      "the doubled branch from an orbit branch's period doubling (with their periods, amplitudes "
                      "and Floquet multipliers; [orbit] keys)");
  cmd_trace->add_option("--free", trace.free,
                        "the curve's second parameter, with [continuation]'s range, stops and steps (default: "
                        "continuation.parameter)");
  cmd_trace->add_flag("--force", trace.force,
                      "start from a stored point that another problem, physics or parameter value made, or a switch at "
                      "a row that is not a located branch point");
  cmd_trace->add_flag("--fresh", trace.fresh, "discard an unfinished OUT.h5.part instead of continuing it");
  cmd_trace->add_option("--set", trace.overrides, "override a scene key: section.key=value (repeatable)");
  cmd_trace->add_flag("--help-scene", trace_help_scene, "list every scene key with its default, range and doc");
  cmd_trace->footer(keller::exit_code::help);

  keller::EvolveArguments evolve;
  bool evolve_help_scene = false;
  CLI::App* cmd_evolve = app.add_subcommand(
      "evolve", "integrate B du/dt = -F in time from a steady state or a stored branch point (adaptive BDF2)");
  cmd_evolve->add_option("scene", evolve.scene, "scene file (TOML); [evolve] sets the time span and the perturbation");
  cmd_evolve->add_option("-o,--output", evolve.output,
                         "time-series file (HDF5; default: <scene name>.h5 here); written as OUT.h5.part until the "
                         "run reaches t_end");
  cmd_evolve->add_option("--restart", evolve.restart,
                         "start from a point stored in a branch file: FILE.h5:ROW (ROW a number, 'last' or a located "
                         "point's label such as hopf1: keller info FILE.h5 lists them)");
  cmd_evolve->add_flag("--force", evolve.force,
                       "start from a stored point that another problem, physics or parameter value made");
  cmd_evolve->add_flag("--fresh", evolve.fresh, "discard an unfinished OUT.h5.part instead of continuing it");
  cmd_evolve->add_option("--set", evolve.overrides, "override a scene key: section.key=value (repeatable)");
  cmd_evolve->add_flag("--help-scene", evolve_help_scene, "list every scene key with its default, range and doc");
  cmd_evolve->footer(keller::exit_code::help);

  keller::ExportArguments exp;
  CLI::App* cmd_export = app.add_subcommand("export", "export a branch file: table as CSV, fields as XDMF");
  cmd_export->add_option("branch", exp.input, "branch file written by keller trace (or time series by keller evolve)")
      ->required();
  cmd_export->add_option("--csv", exp.csv, "write the branch table as CSV to this file ('-': the standard output)");
  cmd_export->add_flag("--xdmf", exp.xdmf, "write the fields of the stored solutions and an XDMF file for ParaView");
  cmd_export->add_option(
      "--orbit", exp.orbit,
      "an orbit branch's row (or label, e.g. stop1): the orbit over one period as fields at --frames "
      "+ 1 times and an XDMF animation, BRANCH-orbitROW.h5 and .xdmf");
  cmd_export
      ->add_option("--frames", exp.frames,
                   "frames of the --orbit animation (default: the branch's orbit.frames, 40 unless set)")
      ->check(CLI::Range(2, 100000));
  cmd_export->footer(keller::exit_code::help);

  keller::InfoArguments info;
  CLI::App* cmd_info = app.add_subcommand(
      "info", "what a file keller wrote is: its kind, problem, scene, provenance, stored rows and point labels");
  cmd_info->add_option("file", info.file, "a file of keller solve, trace, evolve or study (HDF5)")->required();
  cmd_info->add_flag("--scene", info.scene, "print the whole resolved scene stored in the file (every key)");
  cmd_info->footer(keller::exit_code::help);

  keller::StudyArguments study;
  CLI::App* cmd_study = app.add_subcommand(
      "study", "run a study: a family of traces or solves over overrides of a base scene (here, or under mpirun)");
  cmd_study->add_option("study", study.study, "study file (TOML)");
  cmd_study->add_option("--jobs,-j", study.jobs, "worker processes on this machine (default: one per core)")
      ->check(CLI::Range(1, 4096));
  cmd_study->add_option("-o,--output", study.folder, "folder of the study's files (default: <study name> here)");
  cmd_study->footer(keller::exit_code::help);
  cmd_study->require_subcommand(0, 1);
  CLI::App* study_list =
      cmd_study->add_subcommand("list", "list the tasks, one a line: index, status, name, overrides");
  CLI::App* study_run = cmd_study->add_subcommand("run", "run one task here (for batch schedulers: --task K)");
  CLI::App* study_collect = cmd_study->add_subcommand("collect", "collect the tasks' results into STUDY.csv and .h5");
  for (CLI::App* sub : {study_list, study_run, study_collect}) {
    sub->add_option("study", study.study, "study file (TOML)")->required();
    sub->add_option("-o,--output", study.folder, "folder of the study's files (default: <study name> here)");
  }
  study_run->add_option("--task", study.task, "index of the task (keller study list)")->required();

  try {
    app.parse(argc, argv);
    refuse_empty_values(app);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // every usage error has the same code (CLI11's own are 105-109)
    fmt::print(stderr, "keller: error: {}\nRun 'keller --help' (or 'keller COMMAND --help') for the usage.\n",
               e.what());
    return keller::exit_code::usage;
  }

  // solve, trace and evolve: --help-scene lists the keys, else a scene file is needed
  const auto scene_command = [](const char* command, bool help_scene, const std::string& scene,
                                const std::function<void(keller::SceneSchema&)>& keys, const auto& run) {
    if (help_scene) {
      fmt::print("{}", keller::scene_help(keys));
      return keller::exit_code::ok;
    }
    if (scene.empty()) {
      fmt::print(stderr, "keller: error: {0} needs a scene file (keller {0} SCENE.toml -o OUT.h5)\n", command);
      return keller::exit_code::usage;
    }
    return run();
  };
  if (cmd_solve->parsed())
    return scene_command("solve", solve_help_scene, solve.scene, {}, [&] { return keller::run_solve(solve); });
  if (cmd_trace->parsed())
    return scene_command("trace", trace_help_scene, trace.scene, keller::declare_trace_keys,
                         [&] { return keller::run_trace(trace); });
  if (cmd_evolve->parsed())
    return scene_command("evolve", evolve_help_scene, evolve.scene, keller::declare_evolve_keys,
                         [&] { return keller::run_evolve(evolve); });
  if (cmd_export->parsed()) return keller::run_export(exp);
  if (cmd_info->parsed()) return keller::run_info(info);
  if (cmd_study->parsed()) {
    study.action = study_list->parsed()      ? "list"
                   : study_run->parsed()     ? "run"
                   : study_collect->parsed() ? "collect"
                                             : "";
    if (study.study.empty()) {
      fmt::print(stderr, "keller: error: study needs a study file (keller study STUDY.toml)\n");
      return keller::exit_code::usage;
    }
    return keller::run_study_command(study, argc, argv);
  }
  return keller::exit_code::ok;
}

}  // namespace

namespace keller {

void use_native_blas_kernels(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE")) return;  // the user's choice, or this program run again
  const char* keep = std::getenv("KELLER_BLAS_KERNELS");
  if (keep && std::strcmp(keep, "keep") == 0) return;
  // started by the dynamic loader named on the command line (ld.so keller ...), or a static program:
  // /proc/self/exe is not the program that argv names
  if (getauxval(AT_BASE) == 0) return;
  const std::string better = better_blas_core();
  if (better.empty()) return;
  if (setenv("OPENBLAS_CORETYPE", better.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("OPENBLAS_CORETYPE");  // the exec failed: go on with the kernels loaded
}

int run_command_line(int argc, char** argv) {
  Provenance::record_command_line(argc, argv);
  default_blas_thread_policy(true);  // one BLAS thread for small matrices (core/BlasThreads.hpp)
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc&) {
    fmt::print(stderr,
               "keller: error: not enough memory for this problem (a mesh or grid size in the scene is too "
               "large for this machine); nothing written\n");
    return exit_code::usage;
  } catch (const std::exception& e) {  // the last resort: every command reports its own failures
    RunSummary unreported;
    return fail_unexpected(unreported, e);
  }
}

}  // namespace keller
