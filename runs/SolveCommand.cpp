#include "runs/SolveCommand.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "continuation/StartSolver.hpp"
#include "core/Newton.hpp"
#include "core/SolutionWriter.hpp"
#include "core/SparseLU.hpp"
#include "runs/OutputFile.hpp"
#include "runs/SceneLoader.hpp"

namespace keller {

int run_solve(const SolveArguments& args) {
  namespace fs = std::filesystem;
  LoadedScene loaded;
  std::unique_ptr<Problem> problem;
  std::string out = args.output;
  try {
    loaded = load_scene(args.scene, {}, args.overrides);
    if (out.empty()) out = fs::path(args.scene).stem().string() + ".h5";
    check_output_path(out);
    fmt::print("{}\n", loaded.scene.resolved_toml());
    problem = loaded.type->build(loaded.scene);
  } catch (const SceneError& e) {
    fmt::print(stderr, "keller: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: {}: {}\n", args.scene, e.what());
    return 2;
  }
  const Scene& scene = loaded.scene;
  fmt::print("problem: {}\n", problem->summary());

  NewtonSolver newton(*problem, newton_options_from(scene), sparse_lu_options_from(scene));
  Vector u = problem->initial_guess();
  print_newton_header();
  NewtonResult res = newton.solve(u, print_newton_row);
  const StartOptions start_options = StartOptions::from_scene(scene);
  if (!res.converged() && start_options.path != StartOptions::Path::Off) {
    // from an easier state by continuation (StartSolver), then Newton's table from there
    fmt::print("Newton from the initial guess failed ({}); continuing from an easier state\n", res.status.describe());
    StartSolver start(*problem, newton_options_from(scene), sparse_lu_options_from(scene), start_options,
                      [](const std::string& line) { fmt::print("{}\n", line); });
    Vector v = problem->initial_guess();
    const StartResult reached = start.reach(v);
    if (reached.status.is_ok()) {
      fmt::print("reached by {} ({} points, {} factorisations)\n", reached.path, reached.steps, reached.factorisations);
      u = std::move(v);
      res = newton.solve(u, print_newton_row);
    } else {
      fmt::print("no continuation path: {}\n", reached.status.describe());
    }
  }
  const auto& lu = newton.lu().statistics();
  fmt::print("  final |F| = {:.4e} after {} iterations ({} factorisations), {:.3f} s (assembly {:.3f}, factorisation "
             "{:.3f}, solve {:.3f}, line search {:.3f})\n",
             res.residual_norm, res.iterations, res.factorisations, res.seconds, res.assembly_seconds,
             res.factor_seconds, res.solve_seconds, res.line_search_seconds);
  if (lu.factorisations > 0)
    fmt::print("  LU: n = {}, nnz(A) = {}, nnz(L+U) = {:.0f} (fill {:.1f}x), ordering {}\n", lu.n, lu.nnz_matrix,
               lu.nnz_lu, lu.nnz_lu / static_cast<double>(lu.nnz_matrix), lu.ordering_used);
  if (!res.converged()) {
    fmt::print(stderr, "keller: Newton failed: {}; no output written\n", res.status.describe());
    return 1;
  }

  std::vector<double> obs;
  if (problem->observables(u, obs).is_ok()) {
    const auto names = problem->observable_names();
    for (size_t i = 0; i < names.size(); ++i) fmt::print("  {} = {:.10g}\n", names[i], obs[i]);
  }

  const std::string part = out + ".part";
  try {
    {
      H5File file(part, H5File::Mode::Create);
      write_run_header(file, scene, *problem);
      write_solution(file, "/solution", *problem, u);
      std::vector<double> hist;
      for (const auto& it : res.history)
        hist.insert(hist.end(), {static_cast<double>(it.iteration), it.residual_norm, it.update_norm, it.step_length,
                                 it.seconds, it.assembly_seconds, it.factor_seconds, it.solve_seconds});
      file.write_matrix("/solution/newton", hist.data(), static_cast<long>(res.history.size()), 8);
      file.set_attribute("/solution/newton", "columns",
                         std::string("iteration,residual_norm,update_norm,step_length,seconds,assembly_seconds,"
                                     "factor_seconds,solve_seconds"));
      file.set_attribute("/solution/newton", "final_residual_norm", res.residual_norm);
      const SolutionFields f = problem->fields(u);
      if (f.mesh) write_mesh(file, "/mesh", *f.mesh);
      file.close();
      if (f.mesh && scene.boolean("output.xdmf"))
        write_xdmf(xdmf_path_for(out), fs::path(out).filename().string(), "mesh", *f.mesh,
                   {{"solution/fields", "solution", 0.0}}, f);
    }
    fs::rename(part, out);
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(part, ec);
    fmt::print(stderr, "keller: error writing output: {}\n", e.what());
    return 2;
  }
  fmt::print("wrote {}\n", out);
  return 0;
}

}  // namespace keller
