// Benchmark (not a test): cost of one Newton step for the rigid-channel problem on the fluid
// parts of meshes M1..M5 -- unknowns, nonzeros, LU fill, and the time of assembly (residual +
// exact Jacobian), numeric factorisation and solve, plus peak memory. The speed floor is one
// numeric factorisation per Newton step; the goal is assembly <= 30% of factorisation on M2.
//
// Usage: bench_channel [--meshes M1,M2,M3,M4,M5] [--ordering amd|metis|cholmod|best]
//                      [--strategy auto|unsymmetric|symmetric] [--repeat N] [--re RE]
#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "core/SparseLU.hpp"
#include "problems/ChannelProblem.hpp"

using namespace keller;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

template <class F>
double time_median(int repeat, F&& f) {
  std::vector<double> t;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return median(t);
}

double max_rss_mb() {
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  return r.ru_maxrss / 1024.0;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> meshes = {"M1", "M2", "M3", "M4", "M5"};
  SparseLUOptions lu_opt;
  int repeat = 5;
  double Re = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
      return argv[++i];
    };
    if (a == "--meshes") meshes = split(next());
    else if (a == "--ordering") lu_opt.ordering = ordering_from_string(next());
    else if (a == "--strategy") {
      const std::string s = next();
      lu_opt.strategy = s == "symmetric"     ? SparseLUOptions::Strategy::Symmetric
                        : s == "unsymmetric" ? SparseLUOptions::Strategy::Unsymmetric
                                             : SparseLUOptions::Strategy::Auto;
    } else if (a == "--repeat") repeat = std::stoi(next());
    else if (a == "--re") Re = std::stod(next());
    else {
      fmt::print(stderr, "unknown argument {}\n", a);
      return 2;
    }
  }
  fmt::print("rigid channel, Newtonian, Re = {}, ordering {}, median of {} runs\n", Re, to_string(lu_opt.ordering), repeat);
  fmt::print("{:>4} {:>6} {:>8} {:>9} {:>10} {:>6} {:>9} {:>9} {:>9} {:>9} {:>7} {:>8} {:>8}\n", "mesh", "elems",
             "unknowns", "nnz(J)", "nnz(L+U)", "fill", "resid ms", "assem ms", "factor ms", "solve ms",
             "assem/f", "LU MB", "RSS MB");
  for (const std::string& name : meshes) {
    ChannelOptions o;
    o.mesh = ChannelMeshSpec::preset(name);
    o.fluid.Re = Re;
    o.fluid.inertia = Re > 0;
    o.Gamma = 4.95e-4;
    ChannelProblem p(o);
    Vector u = p.initial_guess(), F;
    SparseMatrix J = p.jacobian_pattern();
    SparseLU lu(lu_opt);
    p.jacobian(u, F, J);
    lu.analyze(J);
    const double t_res = time_median(repeat, [&] { p.residual(u, F); });
    const double t_asm = time_median(repeat, [&] { p.jacobian(u, F, J); });
    const double t_fac = time_median(repeat, [&] { lu.factorize(J); });
    Vector x;
    const double t_sol = time_median(repeat, [&] { lu.solve(F, x); });
    const auto& s = lu.statistics();
    fmt::print("{:>4} {:>6} {:>8} {:>9} {:>10.0f} {:>6.2f} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f} {:>7.2f} {:>8.1f} {:>8.1f}\n",
               name, p.mesh().num_elements(), p.size(), J.nonZeros(), s.nnz_lu, s.nnz_lu / J.nonZeros(), 1e3 * t_res,
               1e3 * t_asm, 1e3 * t_fac, 1e3 * t_sol, t_asm / t_fac, s.peak_memory_bytes / 1048576.0, max_rss_mb());
  }
  return 0;
}
