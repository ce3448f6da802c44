// Benchmark (not a test): what one residual F(u), one evaluation of the time terms B(u) udot and
// one of both together (time_dependent_residual: one pass over the elements) cost on a scene's
// problem, per call, and the Jacobian for scale. A linearised pass of periodic-
// orbit shooting (docs/periodic_orbits.md) spends about half its time in them: each GMRES product
// is two of each, evolve's chord iteration one.
//
// Usage: bench_residual SCENE.toml [--calls N] [--repeat N] [--set section.key=value]...
// Prints the machine, the problem and, per repeat, microseconds per call of each (the fastest of
// five batches of N calls), then the same per term of an assembled problem.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/AssembledProblem.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "runs/bench/NewtonStepTiming.hpp"

using namespace keller;
using keller::bench::machine;

int main(int argc, char** argv) {
  if (argc < 2) {
    fmt::print(stderr, "usage: bench_residual SCENE.toml [--calls N] [--repeat N] [--set k=v]...\n");
    return 2;
  }
  const std::string scene = argv[1];
  int calls = 2000, repeat = 3;
  std::vector<std::string> overrides;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--calls" && i + 1 < argc)
      calls = std::atoi(argv[++i]);
    else if (a == "--repeat" && i + 1 < argc)
      repeat = std::atoi(argv[++i]);
    else if (a == "--set" && i + 1 < argc)
      overrides.emplace_back(argv[++i]);
    else {
      fmt::print(stderr, "unknown argument {}\n", a);
      return 2;
    }
  }
  LoadedScene loaded;
  try {
    loaded = load_scene(scene, declare_trace_keys, overrides);
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_residual: {}\n", e.what());
    return 2;
  }
  auto problem = loaded.type->build(loaded.scene);
  const Vector u = problem->initial_guess();
  // a rate of the size of the state, varied in every entry
  Vector udot(u.size());
  for (long i = 0; i < udot.size(); ++i) udot[i] = 1e-3 * std::sin(0.7 * static_cast<double>(i));
  fmt::print("{}\n{}\n{}\n{} calls a figure\n", machine(), scene, problem->summary(), calls);
  Vector F, R;
  SparseMatrix J = problem->jacobian_pattern();
  // the fastest of 5 batches of n calls: a shared machine only ever slows a batch down
  auto per_call = [&](auto&& f, int n) {
    double best = 1e300;
    for (int batch = 0; batch < 5; ++batch) {
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < n; ++k) f();
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / n);
    }
    return 1e6 * best;
  };
  bool has_time = true;
  try {
    problem->time_residual(u, udot, R);
  } catch (const std::exception&) {
    has_time = false;
  }
  fmt::print("{:>8} {:>14} {:>14} {:>16} {:>14}\n", "repeat", "residual us", "time terms us", "F + B udot us",
             "jacobian us");
  Vector G;
  for (int r = 0; r < repeat; ++r) {
    const double f = per_call([&] { (void)problem->residual(u, F); }, calls);
    const double t = has_time ? per_call([&] { (void)problem->time_residual(u, udot, R); }, calls) : 0.0;
    const double g = has_time ? per_call([&] { (void)time_dependent_residual(*problem, u, udot, G); }, calls) : 0.0;
    const double j = per_call([&] { (void)problem->jacobian(u, F, J); }, std::max(calls / 20, 1));
    fmt::print("{:>8} {:>14.2f} {:>14.2f} {:>16.2f} {:>14.2f}\n", r + 1, f, t, g, j);
  }
  // per term: each item's residual and time terms, gathered as the assembler does
  if (const auto* assembled = dynamic_cast<const AssembledProblem*>(problem.get())) {
    fmt::print("\nper term, us a call of all its items:\n{:<28} {:>6} {:>12} {:>12}\n", "term", "items", "residual",
               "time terms");
    for (const auto& tp : assembled->assembler().terms()) {
      const Term& t = *tp;
      std::vector<int> dofs(static_cast<size_t>(t.local_size()));
      std::vector<double> ul(dofs.size()), vl(dofs.size()), rl(static_cast<size_t>(t.local_rows()));
      auto sweep = [&](bool rate) {
        for (int item = 0; item < t.num_items(); ++item) {
          t.item_dofs(item, dofs.data());
          for (size_t j = 0; j < dofs.size(); ++j) {
            ul[j] = u[dofs[j]];
            vl[j] = udot[dofs[j]];
          }
          (void)(rate ? t.rate(item, ul.data(), vl.data(), rl.data()) : t.residual(item, ul.data(), rl.data()));
        }
      };
      const double f = per_call([&] { sweep(false); }, calls);
      const double r = t.has_mass() ? per_call([&] { sweep(true); }, calls) : 0.0;
      fmt::print("{:<28} {:>6} {:>12.2f} {:>12.2f}\n", t.name(), t.num_items(), f, r);
    }
  }
  fmt::print("{}\n", machine());
  return 0;
}
