// Benchmark (not a test): MUMPS's factorisation of one matrix with each fill-reducing ordering
// keller offers, and the estimated flops of every candidate of `best` -- a model grid, or any
// matrix in Matrix Market form (the other benchmarks' --dump-matrix writes keller's Jacobians).
//
// Usage: bench_orderings [--grid NXxNY] [--stencil 5|9] [--matrix FILE.mtx] [--repeat N]
//
// A grid is runs/bench/ModelGrid's: the Laplacian-like pattern of an NX x NY grid of points
// with the 5- or 9-point stencil (nonsingular, unsymmetric values), as the ordering tests use it. Prints, per ordering
// (amd, metis, best), the ordering used, nnz(L+U), MUMPS's flop count, the analysis and the median factorisation time.
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include <unsupported/Eigen/SparseExtra>

#include "core/FillOrdering.hpp"
#include "core/SparseLU.hpp"
#include "runs/bench/ModelGrid.hpp"
#include "runs/bench/NewtonStepTiming.hpp"

using namespace keller;

int main(int argc, char** argv) {
  int nx = 150, ny = 150, stencil = 5, repeat = 3;
  std::string matrix;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        fmt::print(stderr, "{} needs a value\n", a);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--grid") {
      const std::string g = next();
      if (std::sscanf(g.c_str(), "%dx%d", &nx, &ny) != 2 || nx < 1 || ny < 1) {
        fmt::print(stderr, "--grid takes NXxNY, e.g. 300x300\n");
        return 2;
      }
    } else if (a == "--stencil") {
      stencil = std::atoi(next().c_str());
    } else if (a == "--matrix") {
      matrix = next();
    } else if (a == "--repeat") {
      repeat = std::max(1, std::atoi(next().c_str()));
    } else {
      fmt::print(stderr, "usage: bench_orderings [--grid NXxNY] [--stencil 5|9] [--matrix FILE.mtx] [--repeat N]\n");
      return 2;
    }
  }
  if (!mumps_available()) {
    fmt::print(stderr, "this keller is built without MUMPS\n");
    return 2;
  }
  SparseMatrix A;
  if (!matrix.empty()) {
    if (!Eigen::loadMarket(A, matrix) || A.rows() != A.cols() || A.rows() == 0) {
      fmt::print(stderr, "{}: not a square Matrix Market matrix\n", matrix);
      return 2;
    }
    A.makeCompressed();
    fmt::print("{}: {} unknowns, {} entries\n", matrix, A.rows(), A.nonZeros());
  } else {
    A = bench::model_grid(nx, ny, stencil == 9);
    fmt::print("{} x {} grid, {}-point stencil: {} unknowns, {} entries\n", nx, ny, stencil == 9 ? 9 : 5, A.rows(),
               A.nonZeros());
  }
  fmt::print("METIS {}; median of {} factorisations\n", nested_dissection_available() ? "built in" : "missing", repeat);
  fmt::print("{:>8} {:>8} {:>12} {:>8} {:>10} {:>10}\n", "ordering", "used", "nnz(L+U)", "GFlop", "analy ms",
             "factor ms");
  for (auto o : {SparseLUOptions::Ordering::Amd, SparseLUOptions::Ordering::Metis, SparseLUOptions::Ordering::Best}) {
    SparseLUOptions opt;
    opt.backend = SparseLUOptions::Backend::Mumps;
    opt.ordering = o;
    SparseLU lu(opt);
    if (!lu.analyze(A).is_ok()) {
      fmt::print("{:>8} analysis failed\n", to_string(o));
      continue;
    }
    const double factor = bench::median_time(repeat, [&] { lu.factorize(A); });
    const SparseLU::Statistics& s = lu.statistics();
    fmt::print("{:>8} {:>8} {:>12.0f} {:>8.4g} {:>10.1f} {:>10.1f}\n", to_string(o), s.ordering_used, s.nnz_lu,
               s.flops * 1e-9, 1e3 * s.analyze_seconds, 1e3 * factor);
    if (!s.ordering_trials.empty()) {
      fmt::print("{:>8} estimated GFlop of the candidates:", "");
      for (const OrderingTrial& t : s.ordering_trials) fmt::print(" {} {:.4g}", t.name, t.flops * 1e-9);
      fmt::print("\n");
    }
  }
  return 0;
}
