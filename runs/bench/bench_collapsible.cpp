// Benchmark (not a test): cost of one Newton step of the fully coupled collapsible channel
// (Oldroyd-B by default; Wi = 0.1, Gamma = 4.95e-5, Pe = 0.04, t = 0.4) at the converged
// solution on meshes M1..M3 (and finer): unknowns, nonzeros, LU fill, assembly (residual + exact
// Jacobian with the shape derivatives), numeric factorisation and solve. Goals (issue 5):
// assembly <= 30% of factorisation; a continuation point (about 3 Newton steps) on M2 < 1 s.
//
// Usage: bench_collapsible [--meshes M1,M2,M3] [--fluid newtonian|oldroyd-b|fene-p|owens]
//                          [--ordering amd|metis|cholmod|best] [--repeat N]
//                          [--strategy auto|symmetric|unsymmetric] [--pivot-tolerance T]
//                          [--dump-matrix PREFIX] [--backend auto|umfpack|mumps[,...]]
// --backend with a list times each mesh with each backend in turn (one row each), so that their ratios come
// from one run.
// --dump-matrix writes each mesh's Jacobian at the converged state as PREFIX_<mesh>.mtx (Matrix
// Market), for factorising it with another sparse direct solver.
#include <fmt/format.h>

#include <string>
#include <vector>

#include "core/Newton.hpp"
#include "problems/channel/CollapsibleChannelProblem.hpp"
#include "runs/bench/NewtonStepTiming.hpp"

using namespace keller;

int main(int argc, char** argv) {
  std::vector<std::string> meshes = {"M1", "M2", "M3"};
  FluidModel model = FluidModel::OldroydB;
  int repeat = 3;
  std::vector<SparseLUOptions::Backend> backends = {SparseLUOptions::Backend::Auto};
  SparseLUOptions lu_opt;
  lu_opt.ordering = ordering_from_string("best");  // as in the collapsible scenes
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
    } else if (a == "--fluid") {
      model = fluid_model_from_string(next());
    } else if (a == "--repeat") {
      repeat = std::stoi(next());
    } else if (a == "--ordering") {
      lu_opt.ordering = ordering_from_string(next());
    } else if (a == "--strategy") {
      lu_opt.strategy = strategy_from_string(next());
    } else if (a == "--dump-matrix") {
      dump = next();
    } else if (a == "--pivot-tolerance") {
      lu_opt.pivot_tolerance = std::stod(next());
    } else {
      fmt::print(stderr, "unknown argument {}\n", a);
      return 2;
    }
  }
  fmt::print("collapsible channel, {} fluid, Gamma = 4.95e-5, Wi = 0.1, ordering {}, median of {} runs\n",
             to_string(model), to_string(lu_opt.ordering), repeat);
  bench::print_header();
  for (const std::string& name : meshes) {
    CollapsibleOptions o;
    o.mesh = ChannelMeshSpec::preset(name);
    o.fluid.model = model;
    o.Gamma = 4.95e-5;
    o.fluid.Wi = 0.1;
    if (model == FluidModel::Owens) o.fluid.profile = ProfileKind::FullyDeveloped;
    CollapsibleChannelProblem p(o);
    Vector u = p.initial_guess();
    NewtonSolver newton(p, {}, lu_opt);
    const NewtonResult r = newton.solve(u);
    if (!r.converged()) {
      fmt::print(stderr, "{}: Newton did not converge ({})\n", name, r.status.describe());
      return 1;
    }
    if (!dump.empty() && !bench::dump_jacobian(p, u, dump + "_" + name + ".mtx")) {
      fmt::print(stderr, "cannot write the Jacobian of {} to {}_{}.mtx\n", name, dump, name);
      return 1;
    }
    bench::time_and_print(name, p.mesh().num_elements(), p, u, lu_opt, backends, repeat);
  }
  return 0;
}
