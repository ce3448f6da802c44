// keller: continuation and bifurcation of steady flows. Command-line entry point.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "runs/SceneLoader.hpp"
#include "runs/SolveCommand.hpp"

int main(int argc, char** argv) {
  CLI::App app{"keller: continuation and bifurcation toolkit for steady flows"};
  app.require_subcommand(1);

  keller::SolveArguments solve;
  bool solve_help_scene = false;
  CLI::App* cmd_solve = app.add_subcommand("solve", "solve one steady state of a scene by Newton's method");
  cmd_solve->add_option("scene", solve.scene, "scene file (TOML)");
  cmd_solve->add_option("-o,--output", solve.output, "output HDF5 file (default: <scene name>.h5 here)");
  cmd_solve->add_flag("--help-scene", solve_help_scene, "list every scene key with its default, range and doc");

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
  return 0;
}
