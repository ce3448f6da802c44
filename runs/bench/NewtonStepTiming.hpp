// Shared by the benchmarks: the cost of one Newton step of a problem at a state -- assembly
// (residual + exact Jacobian), numeric factorisation and solve, medians of repeated runs -- and
// the table row that prints it.
#pragma once

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unsupported/Eigen/SparseExtra>

#include "core/Problem.hpp"
#include "core/SparseLU.hpp"

namespace keller::bench {

struct StepTiming {
  std::string backend, ordering;  // of the LU
  int unknowns = 0;
  long nnz = 0;
  double nnz_lu = 0;
  // seconds; solve with the LU's refinement steps (at most 2), plain_solve without (the continuation's)
  double residual = 0, assembly = 0, analysis = 0, factor = 0, solve = 0, plain_solve = 0;
  double lu_mb = 0, rss_mb = 0;
  double gflop = 0;                   // of one numeric factorisation
  std::vector<OrderingTrial> trials;  // the candidates of ordering `best` (MUMPS)
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
  s.analysis = lu.statistics().analyze_seconds;
  s.residual = median_time(repeat, [&] { p.residual(u, F); });
  s.assembly = median_time(repeat, [&] { p.jacobian(u, F, J); });
  s.factor = median_time(repeat, [&] { lu.factorize(J); });
  s.solve = median_time(repeat, [&] { lu.solve(F, x); });
  s.plain_solve = median_time(std::max(repeat, 5), [&] { lu.solve(F, x, false, 0); });
  s.backend = lu.statistics().backend;
  s.ordering = lu.statistics().ordering_used;
  s.trials = lu.statistics().ordering_trials;
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

// The machine's memory read bandwidth for one thread, bytes per second: the best of 5 sums over
// 512 MB, far beyond any cache (a plain solve reads each entry of L and U once, from memory).
// The machine a benchmark ran on: CPU model, cores, BLAS threads, load average (one line).
inline std::string machine() {
  std::string model = "?";
  std::ifstream cpu("/proc/cpuinfo");
  for (std::string line; std::getline(cpu, line);)
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  double load[3] = {0, 0, 0};
  if (getloadavg(load, 3) < 0) load[0] = load[1] = load[2] = -1;
  const char* threads = std::getenv("OPENBLAS_NUM_THREADS");
  return fmt::format("machine: {}, {} cores, BLAS threads {}, load average {:.2f} {:.2f} {:.2f}", model,
                     std::thread::hardware_concurrency(), threads ? threads : "default (all cores)", load[0], load[1],
                     load[2]);
}

inline double read_bandwidth() {
  static const double measured = [] {
    constexpr size_t kDoubles = size_t{64} << 20;
    std::vector<double> a(kDoubles, 1.0);
    double best = 0, sink = 0;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
      for (size_t i = 0; i < kDoubles; i += 4) {
        s0 += a[i];
        s1 += a[i + 1];
        s2 += a[i + 2];
        s3 += a[i + 3];
      }
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      sink += s0 + s1 + s2 + s3;
      best = std::max(best, static_cast<double>(kDoubles * sizeof(double)) / t);
    }
    return sink > 0 ? best : 0.0;
  }();
  return measured;
}

// The memory-bandwidth floor of a plain solve as issue 38 put it: nnz(L+U) x 16 bytes (a value
// and its index) at the measured read bandwidth. MUMPS's factors are dense front blocks, 8 bytes
// an entry, so its solves can take half of it (docs/orderings.md).
inline double solve_floor_seconds(double nnz_lu) { return nnz_lu * 16.0 / read_bandwidth(); }

inline void print_header() {
  fmt::print("memory read bandwidth (one thread): {:.1f} GB/s; floor = nnz(L+U) x 16 B at it\n",
             read_bandwidth() * 1e-9);
  fmt::print(
      "{:>6} {:>6} {:>8} {:>9} {:>7} {:>10} {:>10} {:>6} {:>9} {:>9} {:>8} {:>9} {:>9} {:>8} {:>8} {:>7} {:>8} "
      "{:>8} {:>6} {:>7}\n",
      "mesh", "elems", "unknowns", "nnz(J)", "backend", "ordering", "nnz(L+U)", "fill", "resid ms", "assem ms",
      "analy ms", "factor ms", "solve ms", "plain ms", "floor ms", "assem/f", "LU MB", "RSS MB", "GFlop", "GFlop/s");
}

inline void print_row(const std::string& mesh, int elements, const StepTiming& s) {
  fmt::print(
      "{:>6} {:>6} {:>8} {:>9} {:>7} {:>10} {:>10.0f} {:>6.2f} {:>9.2f} {:>9.2f} {:>8.1f} {:>9.2f} {:>9.2f} {:>8.2f} "
      "{:>8.2f} {:>7.2f} {:>8.1f} {:>8.1f} {:>6.2f} {:>7.2f}\n",
      mesh, elements, s.unknowns, s.nnz, s.backend, s.ordering, s.nnz_lu, s.nnz_lu / static_cast<double>(s.nnz),
      1e3 * s.residual, 1e3 * s.assembly, 1e3 * s.analysis, 1e3 * s.factor, 1e3 * s.solve, 1e3 * s.plain_solve,
      1e3 * solve_floor_seconds(s.nnz_lu), s.assembly / s.factor, s.lu_mb, s.rss_mb, s.gflop, s.gflop / s.factor);
  if (!s.trials.empty()) {
    fmt::print("{:>6} best's estimated GFlop:", "");
    for (const OrderingTrial& t : s.trials) fmt::print(" {} {:.2f}", t.name, t.flops * 1e-9);
    fmt::print("\n");
  }
  std::fflush(stdout);
}

// "M1,M2" -> {"M1", "M2"}
inline std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::string item;
  for (std::istringstream in(list); std::getline(in, item, ',');) out.push_back(item);
  return out;
}

// "umfpack,mumps" -> the backends, in that order (each mesh is timed with each in turn, so that
// their ratios come from one run).
inline std::vector<SparseLUOptions::Backend> backends_from_list(const std::string& list) {
  std::vector<SparseLUOptions::Backend> out;
  for (const std::string& b : split(list)) out.push_back(backend_from_string(b));
  return out;
}

// One row per backend for the problem at u.
inline void time_and_print(const std::string& mesh, int elements, Problem& p, const Vector& u, SparseLUOptions lu,
                           const std::vector<SparseLUOptions::Backend>& backends, int repeat) {
  for (const SparseLUOptions::Backend b : backends) {
    lu.backend = b;
    print_row(mesh, elements, time_newton_step(p, u, lu, repeat));
  }
}

}  // namespace keller::bench
