// Benchmark (not a test): cost of one Newton step for the rigid-channel problem on the fluid
// parts of meshes M1..M5 -- unknowns, nonzeros, LU fill, and the time of assembly (residual +
// exact Jacobian), numeric factorisation and solve, plus peak memory. The speed floor is one
// numeric factorisation per Newton step; the goal is assembly <= 30% of factorisation on M2.
//
// Usage: bench_channel [--meshes M1,M2,M3,M4,M5] [--ordering amd|metis|cholmod|best]
//                      [--strategy auto|unsymmetric|symmetric] [--repeat N] [--re RE]
//                      [--backend auto|umfpack|mumps[,...]]
// --backend with a list times each mesh with each backend in turn (one row each).
#include <fmt/format.h>

#include <string>
#include <vector>

#include "core/SparseLU.hpp"
#include "problems/channel/ChannelProblem.hpp"
#include "runs/bench/NewtonStepTiming.hpp"

using namespace keller;

int main(int argc, char** argv) {
  std::vector<std::string> meshes = {"M1", "M2", "M3", "M4", "M5"};
  SparseLUOptions lu_opt;
  std::vector<SparseLUOptions::Backend> backends = {SparseLUOptions::Backend::Auto};
  int repeat = 5;
  double Re = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
      return argv[++i];
    };
    if (a == "--meshes")
      meshes = bench::split(next());
    else if (a == "--ordering")
      lu_opt.ordering = ordering_from_string(next());
    else if (a == "--strategy")
      lu_opt.strategy = strategy_from_string(next());
    else if (a == "--backend")
      backends = bench::backends_from_list(next());
    else if (a == "--repeat")
      repeat = std::stoi(next());
    else if (a == "--re")
      Re = std::stod(next());
    else {
      fmt::print(stderr, "unknown argument {}\n", a);
      return 2;
    }
  }
  fmt::print("rigid channel, Newtonian, Re = {}, ordering {}, median of {} runs\n", Re, to_string(lu_opt.ordering),
             repeat);
  bench::print_header();
  for (const std::string& name : meshes) {
    ChannelOptions o;
    o.mesh = ChannelMeshSpec::preset(name);
    o.fluid.Re = Re;
    o.fluid.inertia = Re > 0;
    o.Gamma = 4.95e-4;
    ChannelProblem p(o);
    bench::time_and_print(name, p.mesh().num_elements(), p, p.initial_guess(), lu_opt, backends, repeat);
  }
  return 0;
}
