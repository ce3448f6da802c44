// keller: continuation and bifurcation of steady flows. Command-line entry point.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "continuation/ContinuationOptions.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/SolveCommand.hpp"
#include "runs/TraceCommand.hpp"

int main(int argc, char** argv) {
  CLI::App app{"keller: continuation and bifurcation toolkit for steady flows"};
  app.require_subcommand(1);

  keller::SolveArguments solve;
  bool solve_help_scene = false;
  CLI::App* cmd_solve = app.add_subcommand("solve", "solve one steady state of a scene by Newton's method");
  cmd_solve->add_option("scene", solve.scene, "scene file (TOML)");
  cmd_solve->add_option("-o,--output", solve.output, "output HDF5 file (default: <scene name>.h5 here)");
  cmd_solve->add_option("--set", solve.overrides, "override a scene key: section.key=value (repeatable)");
  cmd_solve->add_flag("--help-scene", solve_help_scene, "list every scene key with its default, range and doc");

  keller::TraceArguments trace;
  bool trace_help_scene = false;
  CLI::App* cmd_trace = app.add_subcommand("trace", "trace a solution branch by pseudo-arclength continuation");
  cmd_trace->add_option("scene", trace.scene, "scene file (TOML) with a [continuation] section");
  cmd_trace->add_option("-o,--output", trace.output, "branch file (HDF5; default: <scene name>.h5 here)");
  cmd_trace->add_option("--restart", trace.restart, "continue from a stored point: FILE.h5:ROW (ROW a number or 'last')");
  cmd_trace->add_option("--switch", trace.switch_at,
                        "start a new branch at the branch point stored in FILE.h5:ROW, along the null vector of J");
  cmd_trace->add_option("--switch-direction", trace.switch_direction, "side of the old branch to switch to: 1 or -1")
      ->check(CLI::IsMember({-1, 1}));
  cmd_trace->add_option("--set", trace.overrides, "override a scene key: section.key=value (repeatable)");
  cmd_trace->add_flag("--help-scene", trace_help_scene, "list every scene key with its default, range and doc");

  keller::ExportArguments exp;
  CLI::App* cmd_export = app.add_subcommand("export", "export a branch file: table as CSV, fields as XDMF");
  cmd_export->add_option("branch", exp.input, "branch file written by keller trace")->required();
  cmd_export->add_option("--csv", exp.csv, "write the branch table as CSV");
  cmd_export->add_flag("--xdmf", exp.xdmf, "write the fields of the stored solutions and an XDMF file for ParaView");

  CLI11_PARSE(app, argc, argv);

  if (cmd_solve->parsed()) {
    if (solve_help_scene) {
      fmt::print("{}", keller::scene_help());
      return 0;
    }
    if (solve.scene.empty()) {
      fmt::print(stderr, "keller: error: solve needs a scene file (keller solve SCENE.toml -o OUT.h5)\n");
      return 2;
    }
    return keller::run_solve(solve);
  }
  if (cmd_trace->parsed()) {
    if (trace_help_scene) {
      fmt::print("{}", keller::scene_help(keller::declare_trace_keys));
      return 0;
    }
    if (trace.scene.empty()) {
      fmt::print(stderr, "keller: error: trace needs a scene file (keller trace SCENE.toml -o OUT.h5)\n");
      return 2;
    }
    return keller::run_trace(trace);
  }
  if (cmd_export->parsed()) return keller::run_export(exp);
  return 0;
}
