// Benchmark (not a test): cost of one Newton step for Oldroyd-B flow past the confined cylinder
// (beta = 0.59, Wi = 0.3) on meshes C1..C4: unknowns, nonzeros, LU fill, assembly (residual +
// exact Jacobian of the DEVSS-TG/SUPG equations), numeric factorisation and solve. Goal:
// assembly <= 30% of factorisation.
//
// Usage: bench_cylinder [--meshes C1,C2,C3,C4] [--log] [--repeat N] [--ordering amd|metis|cholmod|best]
//                       [--strategy auto|unsymmetric|symmetric] [--dump-matrix PREFIX]
//                       [--backend auto|umfpack|mumps[,...]]
// --backend with a list times each mesh with each backend in turn (one row each), so that their ratios come
// from one run.
// --dump-matrix writes each mesh's Jacobian at the start of the step as PREFIX_<mesh>.mtx
// (Matrix Market), for factorising it with another sparse direct solver.
#include <fmt/format.h>

#include <string>
#include <vector>

#include "problems/cylinder/CylinderProblem.hpp"
#include "runs/bench/NewtonStepTiming.hpp"

using namespace keller;

int main(int argc, char** argv) {
  std::vector<std::string> meshes = {"C1", "C2", "C3", "C4"};
  bool log_form = false;
  int repeat = 3;
  std::vector<SparseLUOptions::Backend> backends = {SparseLUOptions::Backend::Auto};
  SparseLUOptions lu_opt;
  std::string dump;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
      return argv[++i];
    };
    if (a == "--meshes") {
      meshes = bench::split(next());
    } else if (a == "--backend") {
      backends = bench::backends_from_list(next());
    } else if (a == "--log") {
      log_form = true;
    } else if (a == "--repeat") {
      repeat = std::stoi(next());
    } else if (a == "--ordering") {
      lu_opt.ordering = ordering_from_string(next());
    } else if (a == "--strategy") {
      lu_opt.strategy = strategy_from_string(next());
    } else if (a == "--dump-matrix") {
      dump = next();
    } else {
      fmt::print(stderr, "unknown argument {}\n", a);
      return 2;
    }
  }
  fmt::print("confined cylinder, Oldroyd-B, beta = 0.59, Wi = 0.3, {} form, ordering {}, median of {} runs\n",
             log_form ? "log-conformation" : "conformation", to_string(lu_opt.ordering), repeat);
  bench::print_header();
  for (const std::string& name : meshes) {
    CylinderOptions o;
    o.mesh = CylinderMeshSpec::preset(name);
    o.fluid.model = FluidModel::OldroydB;
    o.fluid.log_conformation = log_form;
    o.fluid.beta = 0.59;
    o.fluid.Wi = 0.3;
    CylinderProblem p(o);
    if (!dump.empty()) {
      if (!bench::dump_jacobian(p, p.initial_guess(), dump + "_" + name + ".mtx")) {
        fmt::print(stderr, "cannot write the Jacobian of {} to {}_{}.mtx\n", name, dump, name);
        return 1;
      }
    }
    bench::time_and_print(name, p.mesh().num_elements(), p, p.initial_guess(), lu_opt, backends, repeat);
  }
  return 0;
}
