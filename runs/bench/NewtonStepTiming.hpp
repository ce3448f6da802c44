// Shared by the benchmarks: the cost of one Newton step of a problem at a state -- assembly
// (residual + exact Jacobian), numeric factorisation and solve, medians of repeated runs -- and
// the table row that prints it.
#pragma once

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include <unsupported/Eigen/SparseExtra>

#include "core/Problem.hpp"
#include "core/SparseLU.hpp"

namespace keller::bench {

struct StepTiming {
  int unknowns = 0;
  long nnz = 0;
  double nnz_lu = 0;
  double residual = 0, assembly = 0, factor = 0, solve = 0;  // seconds
  double lu_mb = 0, rss_mb = 0;
  double gflop = 0;  // of one numeric factorisation
};

// Writes J at u as a Matrix Market file (coordinate, real, general), for factorising the same
// matrix with another sparse direct solver; false where J cannot be evaluated or written.
inline bool dump_jacobian(Problem& p, const Vector& u, const std::string& path) {
  Vector F;
  SparseMatrix J = p.jacobian_pattern();
  return p.jacobian(u, F, J).is_ok() && Eigen::saveMarket(J, path);
}

template <class F>
double median_time(int repeat, F&& f) {
  std::vector<double> t;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

inline StepTiming time_newton_step(Problem& p, const Vector& u, const SparseLUOptions& lu_options, int repeat) {
  StepTiming s;
  Vector F, x;
  SparseMatrix J = p.jacobian_pattern();
  SparseLU lu(lu_options);
  p.jacobian(u, F, J);
  lu.analyze(J);
  s.residual = median_time(repeat, [&] { p.residual(u, F); });
  s.assembly = median_time(repeat, [&] { p.jacobian(u, F, J); });
  s.factor = median_time(repeat, [&] { lu.factorize(J); });
  s.solve = median_time(repeat, [&] { lu.solve(F, x); });
  s.unknowns = p.size();
  s.nnz = J.nonZeros();
  s.nnz_lu = lu.statistics().nnz_lu;
  s.lu_mb = lu.statistics().peak_memory_bytes / 1048576.0;
  s.gflop = lu.statistics().flops * 1e-9;
  rusage r{};
  getrusage(RUSAGE_SELF, &r);
  s.rss_mb = r.ru_maxrss / 1024.0;
  return s;
}

inline void print_header() {
  fmt::print("{:>6} {:>6} {:>8} {:>9} {:>10} {:>6} {:>9} {:>9} {:>9} {:>9} {:>7} {:>8} {:>8} {:>6} {:>7}\n", "mesh",
             "elems", "unknowns", "nnz(J)", "nnz(L+U)", "fill", "resid ms", "assem ms", "factor ms", "solve ms",
             "assem/f", "LU MB", "RSS MB", "GFlop", "GFlop/s");
}

inline void print_row(const std::string& mesh, int elements, const StepTiming& s) {
  fmt::print(
      "{:>6} {:>6} {:>8} {:>9} {:>10.0f} {:>6.2f} {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f} {:>7.2f} {:>8.1f} {:>8.1f} "
      "{:>6.2f} {:>7.2f}\n",
      mesh, elements, s.unknowns, s.nnz, s.nnz_lu, s.nnz_lu / static_cast<double>(s.nnz), 1e3 * s.residual,
      1e3 * s.assembly, 1e3 * s.factor, 1e3 * s.solve, s.assembly / s.factor, s.lu_mb, s.rss_mb, s.gflop,
      s.gflop / s.factor);
  std::fflush(stdout);
}

}  // namespace keller::bench
