// Benchmark (not a test): cost of one Newton step of the fully coupled collapsible channel
// (Oldroyd-B by default; Wi = 0.1, Gamma = 4.95e-5, Pe = 0.04, t = 0.4) at the converged
// solution on meshes M1..M3 (and finer): unknowns, nonzeros, LU fill, assembly (residual + exact
// Jacobian with the shape derivatives), numeric factorisation and solve. Goals (issue 5):
// assembly <= 30% of factorisation; a continuation point (about 3 Newton steps) on M2 < 1 s.
//
// Usage: bench_collapsible [--meshes M1,M2,M3] [--fluid newtonian|oldroyd-b|fene-p|owens]
//                          [--ordering amd|metis|cholmod|best] [--repeat N]
//                          [--strategy auto|symmetric|unsymmetric] [--pivot-tolerance T]
//                          [--dump-matrix PREFIX] [--backend auto|umfpack|mumps[,...]] [--modes 1,2]
// --modes with a list times each mesh with a fluid of each number of modes in turn (rows "M2:2m"):
// mode 1 relaxes in lambda with 0.7 of the polymer viscosity, mode 2 in 0.1 lambda with 0.3 (more
// modes split the rest evenly, at times 0.1^k), and the Newton step's ratio to the first count's
// (assembly + factorisation + solve) is printed, from the same run.
// --backend with a list times each mesh with each backend in turn (one row each), so that their ratios come
// from one run.
// --dump-matrix writes each mesh's Jacobian at the converged state as PREFIX_<mesh>.mtx (Matrix
// Market), for factorising it with another sparse direct solver.
#include <fmt/format.h>

#include <cmath>
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
  std::vector<int> mode_counts = {1};
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
    } else if (a == "--modes") {
      mode_counts.clear();
      for (const std::string& m : bench::split(next())) mode_counts.push_back(std::stoi(m));
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
    double first_step = 0;
    for (int modes : mode_counts) {
      CollapsibleOptions o;
      o.mesh = ChannelMeshSpec::preset(name);
      o.fluid.model = model;
      o.Gamma = 4.95e-5;
      o.fluid.Wi = 0.1;
      if (model == FluidModel::Owens) o.fluid.profile = ProfileKind::FullyDeveloped;
      if (modes > 1) {
        o.fluid.modes = {{"m1", 1.0, 0.7}};
        for (int k = 1; k < modes; ++k)
          o.fluid.modes.push_back({fmt::format("m{}", k + 1), std::pow(0.1, k), 0.3 / (modes - 1)});
      }
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
      const std::string label = mode_counts.size() > 1 ? fmt::format("{}:{}m", name, modes) : name;
      if (mode_counts.size() == 1) {
        bench::time_and_print(label, p.mesh().num_elements(), p, u, lu_opt, backends, repeat);
        continue;
      }
      const bench::StepTiming t = bench::time_newton_step(p, u, lu_opt, repeat);
      bench::print_row(label, p.mesh().num_elements(), t);
      const double step = t.assembly + t.factor + t.solve;
      if (first_step == 0)
        first_step = step;
      else
        fmt::print("  {} with {} modes: Newton step {:.1f} ms, {:.2f}x the {}-mode fluid's\n", name, modes, 1e3 * step,
                   step / first_step, mode_counts[0]);
    }
  }
  return 0;
}
